#include "scenario/object_reader.hpp"
#include "session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "physics/checks/telemetry.hpp"
#include "answers.hpp"
#include "race_bots.hpp"
#include "stepping/race_glue.hpp"
#include "token.hpp"

namespace groundsim::session {
namespace {

Applied entry(AppliedKind kind) {
  Applied a;
  a.kind = kind;
  return a;
}

std::string formatTime(double t) {
  std::ostringstream os;
  os << "t=" << t << " s";
  return os.str();
}

}  // namespace

Session::Session(SessionSetup setup, std::shared_ptr<const Model> model, State initial,
                 const ServiceConfig& cfg, Output& out, TimePoint now, const SessionClock& clock)
    : HostedSession(Kind::Simulation, setup.id, setup.token, now),
      setup_(std::move(setup)),
      cfg_(cfg),
      out_(out),
      clock_(clock),
      sim_(model, initial),
      refiner_(setup_.refinement),
      initial_(std::move(initial)),
      budget_(cfg.publish_limit, std::max(1.0, cfg.publish_limit * 0.05)) {
  const Model& m = *model;
  vehicles_ = vehicleWheels(m);
  names_ = std::make_shared<const std::vector<std::string>>(setup_.vehicle_names);
  releaseHeld(now);
  info_.dt = m.opt.dt;
  for (const VehicleWheels& v : vehicles_) info_.wheel_counts.push_back(static_cast<int>(v.wheels.size()));
  steps_per_frame_ = stepsPerFrame(setup_.publish_rate, m.opt.dt);
  if (cfg.replica_interval > 0)
    replica_every_ = std::max<std::int64_t>(1, std::llround(cfg.replica_interval / m.opt.dt));
  anchor_.reset(now, sim_.state().t, setup_.rate);
  race_ = makeRaceGlue(setup_.scenario_json, model);
  if (race_) {
    std::vector<int> road_car;
    for (const VehicleWheels& v : vehicles_) road_car.push_back(v.road_car);
    scenario::RaceSpec spec = race_->race.spec();
    spec.bot_policy_text = setup_.bot_policy;  // read with the scenario, where its files are
    bots_ = RaceBots::make(spec, m, road_car);
  }
  updateInfo(now);
}

void Session::post(const Request& r) {
  std::lock_guard<std::mutex> lk(mailbox_mutex_);
  mailbox_.emplace_back(r);
}

void Session::post(Drive d) {
  std::lock_guard<std::mutex> lk(mailbox_mutex_);
  mailbox_.emplace_back(std::move(d));
}

void Session::post(CarDrive d) {
  std::lock_guard<std::mutex> lk(mailbox_mutex_);
  mailbox_.emplace_back(std::move(d));
}

void Session::stop(std::optional<ReplyTo> reply, std::string reason) {
  std::lock_guard<std::mutex> lk(mailbox_mutex_);
  mailbox_.emplace_back(StopCommand{std::move(reply), std::move(reason)});
}

SessionInfo Session::listing() const {
  std::lock_guard<std::mutex> lk(info_mutex_);
  return info_;
}

void Session::updateInfo(TimePoint) {
  std::lock_guard<std::mutex> lk(info_mutex_);
  info_.session_id = setup_.id;
  info_.name = setup_.name;
  info_.mode = setup_.mode;
  info_.status = status_;
  info_.reason = reason_;
  info_.rate = setup_.rate;
  info_.publish_rate = setup_.publish_rate;
  info_.t = sim_.state().t;
  info_.tick = sim_.state().tick;
  info_.seq = seq_ - 1;
  info_.vehicle_names = setup_.vehicle_names;
}

std::optional<TimePoint> Session::run(TimePoint now) {
  try {
    {
      std::lock_guard<std::mutex> lk(mailbox_mutex_);
      work_.swap(mailbox_);
    }
    for (const Command& c : work_) {
      if (status_ == Status::Stopped) break;  // nothing after a stop
      std::visit([&](const auto& cmd) {
        if constexpr (std::is_same_v<std::decay_t<decltype(cmd)>, Request>) apply(cmd, now);
        else apply(cmd);
      }, c);
    }
    work_.clear();
    if (replicate_again_.exchange(false) && status_ != Status::Stopped && cfg_.replica_interval > 0) {
      out_.publishReplica(scenarioReplica());
      // as the periodic snapshot: once this tick's frame is out
      if (frame_pending_) replica_due_ = true;
      else replicate();
    }
    std::optional<TimePoint> next;
    if (status_ != Status::Stopped) next = advance(now, now + toDuration(cfg_.slice));
    updateInfo(now);
    return next;
  } catch (const std::exception& e) {
    failSafely(e.what());
  } catch (...) {
    failSafely("unknown exception");
  }
  try {
    updateInfo(now);
  } catch (...) {
  }
  return std::nullopt;
}

void Session::abandon(const char* why) noexcept {
  failSafely(why);
  try {
    updateInfo(clock_.now());
  } catch (...) {
  }
}

// The error path must not fail in turn: each part is tried on its own, so
// the session ends diverged and every pending step is answered (with a
// state if one can still be built) whatever else throws.
void Session::failSafely(const char* what) noexcept {
  work_.clear();
  status_ = Status::Diverged;
  std::string why;
  try {
    why = std::string("internal error: ") + (what ? what : "?");
    reason_ = why;
  } catch (...) {
    reason_.clear();
  }
  try {
    event(Severity::Error, ErrorCode::Internal, "session failed at " + formatTime(sim_.state().t) + ": " + why);
  } catch (...) {
  }
  try {
    publishFrame();
  } catch (...) {
    frame_pending_ = false;
  }
  for (const StepJob& j : steps_) {
    try {
      reply(j.reply, false, ErrorCode::Internal, "session failed: " + why, makeFrame(false));
    } catch (...) {
      try {
        reply(j.reply, false, ErrorCode::Internal, "session failed: " + why);
      } catch (...) {
      }
    }
  }
  steps_.clear();
}

// ---- commands -------------------------------------------------------------

void Session::apply(const Request& r, TimePoint now) {
  const ReplyTo to = replyTo(r);
  if (r.op == Op::Reset && r.steps < 0) return raceRespawn(r);
  switch (r.op) {
    case Op::Reset:
      failSteps(ErrorCode::BadRequest, "interrupted by a reset");
      logApplied(entry(AppliedKind::Reset));  // at the tick it left
      resetTo(sim_, cars_, initial_);
      raceReset();
      if (setup_.live_estimate) setup_.live_estimate->reset();
      refiner_.reset();
      status_ = Status::Running;
      reason_.clear();
      releaseHeld(now);
      reanchor(now);
      frame_pending_ = true;
      reply(to, true, ErrorCode::None, "");
      return;
    case Op::Pause:
      if (status_ != Status::Running && status_ != Status::Paused)
        return reply(to, false, ErrorCode::BadRequest, std::string("cannot pause: session is ") + statusName(status_));
      status_ = Status::Paused;
      logApplied(entry(AppliedKind::Pause));
      frame_pending_ = true;  // subscribers see the pause
      return reply(to, true, ErrorCode::None, "");
    case Op::Resume:
      if (status_ != Status::Running && status_ != Status::Paused)
        return reply(to, false, ErrorCode::BadRequest, std::string("cannot resume: session is ") + statusName(status_));
      status_ = Status::Running;
      logApplied(entry(AppliedKind::Resume));
      reanchor(now);
      // the time it stood paused is no one's silence: every held command's
      // timeout counts from the resume (a bot, which commands as the clock
      // runs, would otherwise lose its pedals at every resume)
      for (Held& h : car_held_) h.last = now;
      for (Held& h : drive_held_) h.last = now;
      frame_pending_ = true;
      return reply(to, true, ErrorCode::None, "");
    case Op::Step:
      if (setup_.mode != Mode::Lockstep)
        return reply(to, false, ErrorCode::WrongMode,
                     std::string("step needs lockstep mode; session is ") + modeName(setup_.mode));
      if (status_ == Status::Diverged)
        return reply(to, false, ErrorCode::Diverged, "session diverged: " + reason_ + " (reset it)", makeFrame(false));
      if (status_ == Status::Paused)
        return reply(to, false, ErrorCode::BadRequest, "session is paused (resume it)");
      status_ = Status::Running;  // lockstep ignores the duration
      reason_.clear();
      {
        Applied a = entry(AppliedKind::Step);
        a.steps = r.steps;
        logApplied(std::move(a));
      }
      steps_.push_back(StepJob{to, r.steps});
      return;
    case Op::SetMode: {
      if (r.mode != 0) {
        const Mode m = *modeFromInt(r.mode);  // validated by the service
        if (m != Mode::Lockstep) failSteps(ErrorCode::WrongMode, "mode changed");
        setup_.mode = m;
      }
      if (r.rate > 0) setup_.rate = r.rate;
      if (r.publish_rate > 0) {
        setup_.publish_rate = r.publish_rate;
        steps_per_frame_ = stepsPerFrame(r.publish_rate, sim_.model().opt.dt);
      }
      {
        Applied a = entry(AppliedKind::SetMode);
        a.mode = r.mode;
        a.rate = r.rate;
        a.publish_rate = r.publish_rate;
        logApplied(std::move(a));
      }
      reanchor(now);
      return reply(to, true, ErrorCode::None, "");
    }
    default:
      return reply(to, false, ErrorCode::BadRequest, "not a session request");
  }
}

void Session::apply(const Drive& d) {
  const VehicleWheels& vw = vehicles_.at(d.vehicle);
  Applied a = entry(AppliedKind::Drive);
  a.vehicle = d.vehicle;
  for (size_t k = 0; k < vw.wheels.size() && k < d.wheels.size(); ++k) {
    WheelControl c = d.wheels[k];
    // physics applies any angle it is given: hold it to the wheel's lock
    c.steer = std::clamp(c.steer, -vw.max_steer[k], vw.max_steer[k]);
    a.wheels.push_back(c);
  }
  applyDrive(sim_, vw.wheels, a.wheels);
  drive_held_.at(static_cast<size_t>(d.vehicle)) = Held{d.received, holdsTorque(a.wheels)};
  logApplied(std::move(a));
  last_drive_ = d.received;
  drive_applied_ = clock_.now();
}

// Checked by the service (a road car, values in range); the physics clamps
// and rate-limits what it applies.
void Session::apply(const CarDrive& d) {
  const int c = vehicles_.at(d.vehicle).road_car;
  if (c < 0) return;
  CarControls cc = d.controls;
  cc.wheel_torque = sim_.carControls(c).wheel_torque;  // per-wheel experiment torques are not a driver's
  applyCarControls(sim_, cars_, c, cc);
  Applied a = entry(AppliedKind::Controls);
  a.vehicle = d.vehicle;
  a.controls = cc;
  logApplied(std::move(a));
  car_held_.at(static_cast<size_t>(d.vehicle)) = Held{d.received, holdsPedal(cc)};
}

void Session::apply(const StopCommand& c) {
  failSteps(ErrorCode::BadRequest, "session stopped");
  status_ = Status::Stopped;
  reason_ = c.reason;
  Applied a = entry(AppliedKind::Stop);
  a.reason = c.reason;
  logApplied(std::move(a));
  publishFrame();
  if (c.reply) reply(*c.reply, true, ErrorCode::None, "");
  event(Severity::Info, ErrorCode::None, "session stopped: " + c.reason);
}

void Session::failSteps(ErrorCode code, const std::string& why) {
  for (const StepJob& j : steps_) reply(j.reply, false, code, why, makeFrame(false));
  steps_.clear();
}

void Session::diverged(const std::string& why, ErrorCode code) {
  status_ = Status::Diverged;
  reason_ = why;
  event(Severity::Error, code, "session diverged at " + formatTime(sim_.state().t) + ": " + why);
  publishFrame();
  failSteps(code, "session diverged: " + why);
}

void Session::reanchor(TimePoint now) { anchor_.reset(now, sim_.state().t, setup_.rate); }

// ---- stepping -------------------------------------------------------------

bool Session::finished() const {
  return setup_.mode != Mode::Lockstep && setup_.duration > 0 &&
         sim_.state().t >= setup_.duration - 0.5 * sim_.model().opt.dt;
}

bool Session::stepOnce() {
  if (!setup_.control_tables.empty()) followControlTables(sim_, cars_, setup_.control_tables);
  accuracy::LiveEstimate* live = setup_.live_estimate.get();
  if (live) live->beforeStep(sim_);
  botsDrive();
  raceBeforeStep();
  const double t0 = sim_.state().t;
  if (!sim_.step()) {
    diverged(sim_.state().health_reason, ErrorCode::Diverged);
    return false;
  }
  raceAfterStep(t0);
  if (live) {
    live->afterStep(sim_);
    watchAccuracy();
  }
  if (sim_.model().collisions) reportHits();
  if (sim_.state().tick % steps_per_frame_ == 0) frame_pending_ = true;
  if (replica_every_ > 0 && sim_.state().tick % replica_every_ == 0 && !replaying_) {
    // after this tick's frame: a standby resumes from a published frame and
    // publishes only frames of steps it took (their wheel forces and slips
    // come from its own step's evaluation, as the owner's did; a restored
    // state has no evaluation behind it)
    if (frame_pending_) replica_due_ = true;
    else replicate();
  }
  return true;
}

// A refinement at a safe point: a frame boundary (each published state of
// one setting) with no contact between bodies under way. Logged as an
// applied entry, so that a standby and a re-simulation refine at this tick
// too (applyEntry); the standby's snapshot carries the substeps.
void Session::watchAccuracy() {
  accuracy::LiveEstimate& live = *setup_.live_estimate;
  const bool safe = sim_.state().tick % steps_per_frame_ == 0 && accuracy::safeToRefine(sim_);
  const accuracy::Refiner::Decision d = refiner_.watch(sim_, live, safe);
  if (d.substeps > 0) {
    Applied a = entry(AppliedKind::Refine);
    a.steps = d.substeps;
    logApplied(std::move(a));
  }
  if (!d.message.empty()) event(d.warning ? Severity::Warning : Severity::Info, ErrorCode::None, d.message);
}

// Each hit once, when it ends: a game shows it, a task penalises it, a log
// keeps it. Hard ones (collisions.hard_impact_dv) are warnings.
void Session::reportHits() {
  for (const Hit& h : sim_.takeEndedHits()) {
    const Model& m = sim_.model();
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "hit: %s and %s at (%.2f, %.2f, %.2f) m, closing %.2f m/s, impulse %.4g N s, peak force %.4g N, "
                  "overlap %.3f m, %.3f s%s",
                  m.groups[h.a].name.c_str(), m.groups[h.b].name.c_str(), h.where.x(), h.where.y(), h.where.z(),
                  h.closing_speed, h.impulse, h.peak_force, h.depth, h.end - h.begin + m.opt.dt,
                  h.hard ? " (hard)" : "");
    event(h.hard ? Severity::Warning : Severity::Info, ErrorCode::None, buf);
  }
}

// Each vehicle on its own: a silent player's pedals (or torques) are
// released after the timeout whatever the others send, and the release
// touches no other car. Logged per vehicle, so that re-simulation and a
// standby release the same car at the same tick.
void Session::checkCommandTimeout(TimePoint now) {
  for (size_t v = 0; v < vehicles_.size(); ++v) {
    const VehicleWheels& vw = vehicles_[v];
    // as for drive_t: the pedals are released, steering and gear stay
    expire(car_held_[v], now, v, AppliedKind::ControlsTimeout, "controls", "its throttle and brake",
           [&] { releasePedals(sim_, vw.road_car); });
    expire(drive_held_[v], now, v, AppliedKind::DriveTimeout, "drive", "its torques",
           [&] { releaseDrive(sim_, vw.wheels); });
  }
}

template <class Release>
void Session::expire(Held& h, TimePoint now, size_t v, AppliedKind kind, const char* command, const char* what,
                     Release release) {
  const double limit = cfg_.command_timeout;
  if (!h.held || seconds(now - h.last) <= limit) return;
  h.held = false;
  release();
  Applied a = entry(kind);
  a.vehicle = static_cast<int>(v);
  logApplied(std::move(a));
  const std::string& name = names_ && v < names_->size() ? (*names_)[v] : std::to_string(v);
  event(Severity::Warning, ErrorCode::CommandTimeout,
        std::string("no ") + command + " command for " + name + " (vehicle " + std::to_string(v) + ") for " +
            scenario::formatNumber(limit) + " s: " + what + " set to zero");
}

void Session::releaseHeld(TimePoint now) {
  drive_held_.assign(vehicles_.size(), Held{now, false});
  car_held_.assign(vehicles_.size(), Held{now, false});
}

std::optional<TimePoint> Session::advance(TimePoint now, TimePoint deadline) {
  if (status_ != Status::Running) {
    if (frame_pending_) publishFrame();
    return std::nullopt;
  }
  if (setup_.mode == Mode::Lockstep) return advanceLockstep(deadline);

  const double dt = sim_.model().opt.dt;
  const bool realtime = setup_.mode == Mode::Realtime;
  std::int64_t todo = std::numeric_limits<std::int64_t>::max();
  if (realtime) {
    checkCommandTimeout(now);
    double lag = (anchor_.target(now) - sim_.state().t) / setup_.rate;
    if (lag > cfg_.max_lag) {
      // the pool cannot keep up: drop the backlog rather than run ever later
      if (seconds(now - last_overrun_event_) > 5.0) {
        event(Severity::Warning, ErrorCode::Overrun,
              "real time overrun: " + scenario::formatNumber(lag) + " s behind the wall clock; skipping ahead");
        last_overrun_event_ = now;
      }
      reanchor(now);
    }
    // bounded by max_lag after the check above; clamped all the same
    todo = clampedCount((anchor_.target(now) - sim_.state().t) / dt + 1e-6, 0,
                        std::numeric_limits<std::int64_t>::max());
  }
  for (;;) {
    if (frame_pending_ && !emitFrame(clock_.now())) return budget_.nextToken(clock_.now());
    if (finished()) {
      status_ = Status::Finished;
      reason_ = "reached the duration, " + formatTime(setup_.duration);
      publishFrame();
      return std::nullopt;
    }
    if (todo <= 0) break;
    if (clock_.now() >= deadline) return clock_.now();  // yield the worker, come back at once
    if (!stepOnce()) return std::nullopt;
    --todo;
  }
  // real time, caught up: sleep until the next frame is due
  const std::int64_t tick = sim_.state().tick;
  const double next_frame_t = sim_.state().t + (steps_per_frame_ - tick % steps_per_frame_) * dt;
  return anchor_.wallAt(next_frame_t);
}

std::optional<TimePoint> Session::advanceLockstep(TimePoint deadline) {
  frame_pending_ = false;  // lockstep publishes once per step request
  while (!steps_.empty()) {
    StepJob& job = steps_.front();
    while (job.remaining > 0) {
      if (clock_.now() >= deadline) return clock_.now();
      if (!stepOnce()) return std::nullopt;
      --job.remaining;
    }
    frame_pending_ = false;
    Frame f = makeFrame();
    out_.publishState(f);
    ReplyTo to = job.reply;
    steps_.pop_front();
    reply(to, true, ErrorCode::None, "", std::move(f));
  }
  return std::nullopt;
}

// ---- output ---------------------------------------------------------------

bool Session::emitFrame(TimePoint now) {
  if (!budget_.take(now)) return false;
  publishFrame();
  return true;
}

void Session::publishFrame() {
  frame_pending_ = false;
  // a frame that ends the session carries the log's last entry, so a
  // recorder that has the frame knows how many entries there were
  if (status_ == Status::Finished || status_ == Status::Stopped || status_ == Status::Diverged) {
    Applied a = entry(AppliedKind::End);
    a.reason = reason_;
    logApplied(std::move(a));
  }
  out_.publishState(makeFrame());
  if (replica_due_) {
    replica_due_ = false;
    replicate();
  }
}

void Session::logApplied(Applied a) {
  a.session_id = setup_.id;
  a.seq = applied_seq_++;
  a.frame_seq = seq_;
  a.tick = sim_.state().tick;
  a.t = sim_.state().t;
  a.epoch = epoch();
  out_.publishApplied(a);
}

Frame Session::makeFrame(bool published) {
  Frame f;
  f.session_id = setup_.id;
  // a frame only carried by a reply repeats the last published seq, so that
  // state subscribers never see a gap that is not a loss
  f.seq = published ? seq_++ : seq_ - 1;
  f.mode = setup_.mode;
  f.status = status_;
  f.reason = reason_;
  f.names = names_;
  f.drive_received = last_drive_;
  f.drive_applied = drive_applied_;
  fillFrame(f, sim_, vehicles_);
  if (setup_.live_estimate) f.error_estimate = setup_.live_estimate->estimate();
  f.epoch = epoch();
  return f;
}

void Session::reply(const ReplyTo& to, bool ok, ErrorCode code, std::string error, std::optional<Frame> state) {
  Reply r = makeReply(to, setup_.id, ok, code, std::move(error));
  r.t = sim_.state().t;
  r.state = std::move(state);
  const TimePoint now = clock_.now();
  updateInfo(now);
  r.sessions.push_back(info(now));
  if (ok) out_.publishReply(r);
  else refuse(out_, std::move(r));
}

void Session::event(Severity sev, ErrorCode code, std::string reason) {
  if (replaying_) return;  // published by the owner that first lived it
  Event e = sessionEvent(setup_.id, sev, code, std::move(reason), sim_.state().t);
  e.epoch = epoch();
  out_.publishEvent(e);
}

}  // namespace groundsim::session
