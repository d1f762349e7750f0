// A session's part in a fleet (docs/fleet.md): the replicas its standbys
// keep, and the resumption of a session whose owner was lost. The owner's
// applied-command log is what makes a resumption exact: the standby
// restores the newest snapshot and replays the entries after it at the ticks
// they took effect, through the functions the owner used (applied.hpp).
#include <nlohmann/json.hpp>

#include "experiments/snapshot.hpp"
#include "stepping/race_glue.hpp"
#include "session.hpp"

namespace groundsim::session {
namespace {

// The snapshot binds to its scenario: one of another document is refused.
std::string scenarioHash(const std::string& json) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx",
                static_cast<unsigned long long>(experiments::fnv1a64(json.data(), json.size())));
  return buf;
}

}  // namespace

Replica Session::scenarioReplica() const {
  Replica r;
  r.kind = Replica::Kind::Scenario;
  r.session_id = setup_.id;
  r.epoch = epoch();
  nlohmann::json m;
  m["token"] = setup_.token;
  m["name"] = setup_.name;
  m["duration"] = setup_.duration;
  m["mode"] = static_cast<int>(setup_.mode);
  m["rate"] = setup_.rate;
  m["publish_rate"] = setup_.publish_rate;
  r.meta = m.dump();
  r.data = setup_.scenario_json;
  return r;
}

void Session::replicate() {
  Replica r;
  r.kind = Replica::Kind::Snapshot;
  r.session_id = setup_.id;
  r.epoch = epoch();
  r.tick = sim_.state().tick;
  r.applied_seq = applied_seq_;
  r.frame_seq = seq_;
  experiments::EnvSnapshot s;
  s.state = sim_.state();
  r.data = experiments::encodeSnapshot(scenarioHash(setup_.scenario_json), s);
  nlohmann::json m;
  m["status"] = static_cast<int>(status_);
  m["reason"] = reason_;
  m["mode"] = static_cast<int>(setup_.mode);
  m["rate"] = setup_.rate;
  m["publish_rate"] = setup_.publish_rate;
  m["driven"] = cars_.driven;
  m["frame_pending"] = frame_pending_;
  m["substeps"] = sim_.model().opt.substeps;  // refined since the scenario (applied Refine entries)
  if (race_) m["race"] = raceProgress(*race_);  // laps, gates, best laps: kept through a failover
  r.meta = m.dump();
  out_.publishReplica(r);
}

// One entry of the lost owner's log, at its tick: its effect on the
// simulation (applyEntry, as the re-simulator) and on the session's settings.
std::string Session::replay(const Applied& a) {
  while (sim_.state().tick < a.tick) {
    if (status_ != Status::Running) return "entry " + std::to_string(a.seq) + " steps a session that is not running";
    if (frame_pending_) {  // the owner published this frame before stepping on
      ++seq_;
      frame_pending_ = false;
    }
    if (!stepOnce()) return "diverged while replaying at tick " + std::to_string(sim_.state().tick);
  }
  if (a.tick != sim_.state().tick)
    return "entry " + std::to_string(a.seq) + " at tick " + std::to_string(a.tick) + " is behind the snapshot's " +
           std::to_string(sim_.state().tick);
  // the frame of this tick: published before the entry took effect when
  // the entry names the seq after it (the owner's count is authoritative,
  // also where its publish budget deferred a frame)
  if (frame_pending_ && a.frame_seq > seq_) frame_pending_ = false;
  seq_ = a.frame_seq;
  if (std::string why = applyEntry(sim_, cars_, vehicles_, initial_, a, race_.get()); !why.empty()) return why;
  // and its effect on the session's own settings
  switch (a.kind) {
    // a held command's timeout restarts from the resumption
    case AppliedKind::Drive:
      drive_held_.at(static_cast<size_t>(a.vehicle)) = Held{clock_.now(), holdsTorque(a.wheels)};
      break;
    case AppliedKind::Controls:
      car_held_.at(static_cast<size_t>(a.vehicle)) = Held{clock_.now(), holdsPedal(a.controls)};
      break;
    case AppliedKind::DriveTimeout:
    case AppliedKind::ControlsTimeout:
      if (a.vehicle < 0) releaseHeld(clock_.now());
      else (a.kind == AppliedKind::DriveTimeout ? drive_held_ : car_held_).at(static_cast<size_t>(a.vehicle)).held = false;
      break;
    case AppliedKind::Reset:
      releaseHeld(clock_.now());
      status_ = Status::Running;
      reason_.clear();
      break;
    case AppliedKind::Pause: status_ = Status::Paused; break;
    case AppliedKind::Resume: status_ = Status::Running; break;
    case AppliedKind::SetMode:
      if (auto m = modeFromInt(a.mode); a.mode != 0 && m) setup_.mode = *m;
      if (a.rate > 0) setup_.rate = a.rate;
      if (a.publish_rate > 0) {
        setup_.publish_rate = a.publish_rate;
        steps_per_frame_ = stepsPerFrame(a.publish_rate, sim_.model().opt.dt);
      }
      break;
    case AppliedKind::Stop:
      status_ = Status::Stopped;
      reason_ = a.reason;
      break;
    default: break;
  }
  applied_seq_ = a.seq + 1;
  return "";
}

// Steps with no new input up to `tick`, publishing again the frames the
// owner published on the way, the frame of `tick` itself included: they
// are re-simulated, equal to their first publication bit for bit (a
// recorder or logger counts them as such), and a command taken next is the
// owner's would-be next, after them (the owner applies commands after the
// frame of their tick went out).
std::string Session::fastForward(std::int64_t tick) {
  while (sim_.state().tick < tick && status_ == Status::Running && !finished()) {
    if (frame_pending_) publishFrame();
    if (!stepOnce()) return "diverged while stepping to the owner's last state, at tick " + std::to_string(sim_.state().tick);
  }
  if (sim_.state().tick == tick && frame_pending_) publishFrame();
  return "";
}

std::string Session::resume(const Replica& snapshot, const std::vector<Applied>& log, std::int64_t heard_tick) {
  experiments::EnvSnapshot s;
  try {
    s = experiments::decodeSnapshot(snapshot.data, scenarioHash(setup_.scenario_json));
  } catch (const std::exception& e) {
    return std::string("the snapshot: ") + e.what();
  }
  if (s.state.y.size() != sim_.state().y.size()) return "the snapshot is of another model";
  const nlohmann::json m = nlohmann::json::parse(snapshot.meta, nullptr, false);
  if (!m.is_object()) return "the snapshot's meta is not JSON";
  sim_.restore(s.state);
  if (const int n = m.value("substeps", sim_.model().opt.substeps); n != sim_.model().opt.substeps) {
    if (n < 1 || n > Simulator::kMaxSubsteps) return "the snapshot's substeps: " + std::to_string(n);
    sim_.refine(n);
  }
  seq_ = snapshot.frame_seq;
  applied_seq_ = snapshot.applied_seq;
  status_ = static_cast<Status>(m.value("status", static_cast<int>(Status::Running)));
  reason_ = m.value("reason", std::string());
  if (auto md = modeFromInt(m.value("mode", 0))) setup_.mode = *md;
  setup_.rate = m.value("rate", setup_.rate);
  setup_.publish_rate = m.value("publish_rate", setup_.publish_rate);
  steps_per_frame_ = stepsPerFrame(setup_.publish_rate, sim_.model().opt.dt);
  if (m.contains("driven") && m["driven"].is_array()) cars_.driven = m["driven"].get<std::vector<bool>>();
  frame_pending_ = m.value("frame_pending", true);
  if (race_ && m.contains("race"))
    if (std::string why = raceRestore(*race_, sim_, m["race"]); !why.empty()) return why;
  replaying_ = true;
  std::string why;
  for (const Applied& a : log) {
    if (a.seq < applied_seq_) continue;  // before the snapshot
    // an entry the standby never heard: the replay ends before it (what
    // followed is lost; the caller reports the resumption point)
    if (a.seq != applied_seq_) break;
    if (a.kind == AppliedKind::End) break;  // the owner's last word: nothing follows
    if (why = replay(a); !why.empty()) break;
  }
  // the owner stepped on after its last entry and published what it
  // stepped: a command taken here must take effect after those states, or
  // the states published again from here would differ from them
  if (why.empty() && setup_.mode != Mode::Lockstep) why = fastForward(heard_tick);
  replaying_ = false;
  reanchor(clock_.now());
  updateInfo(clock_.now());
  return why;
}

}  // namespace groundsim::session
