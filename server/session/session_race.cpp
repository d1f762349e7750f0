// A session's race hooks (session.hpp): the race's announcements and
// events around each step, its bots' commands, respawns. Kept apart from
// race_glue.cpp, which the re-simulator links without the hosting layer.
#include "answers.hpp"
#include "race_bots.hpp"
#include "stepping/race_glue.hpp"
#include "session.hpp"

namespace groundsim::session {

void Session::raceBeforeStep() {
  if (!race_) return;
  RaceGlue& g = *race_;
  if (!g.announced) {
    g.announced = true;
    event(Severity::Info, ErrorCode::None, g.race.layoutReason(setup_.vehicle_names));
    event(Severity::Info, ErrorCode::None, g.race.standingsReason(sim_.state().t, setup_.vehicle_names));
  }
  raceHold(g, sim_);
}

void Session::raceAfterStep(double t0) {
  if (!race_) return;
  RaceGlue& g = *race_;
  bool standings = false;
  for (const race::RaceEvent& e : raceStepped(g, sim_, t0)) {
    event(Severity::Info, ErrorCode::None, race::Race::reason(e, setup_.vehicle_names));
    standings = standings || e.kind == race::EventKind::Start || e.kind == race::EventKind::Gate ||
                e.kind == race::EventKind::Lap || e.kind == race::EventKind::Finish;
  }
  if (standings) event(Severity::Info, ErrorCode::None, g.race.standingsReason(sim_.state().t, setup_.vehicle_names));
}

void Session::raceReset() {
  if (race_) raceRestart(*race_, sim_);
  if (bots_) bots_->relocateAll(sim_.state().t);
}

// Before a step, once every control period: each bot's command, applied as
// a player's (Session::apply: clamped, timed out, logged); a bot that has
// finished brakes to a stop. Not while a standby replays the owner's log:
// the bots' commands are in it.
void Session::botsDrive() {
  if (!bots_ || replaying_ || status_ != Status::Running || !bots_->due(sim_.state().tick)) return;
  CarDrive d;
  d.client_id = "bot";
  d.received = clock_.now();
  for (const RaceBots::Command& c : bots_->drive(sim_.model(), sim_.state(), race_->race)) {
    d.vehicle = c.vehicle;
    d.controls = c.controls;
    if (race_->race.standing(c.vehicle).finished) {  // past the flag: slow down and stop on the line
      d.controls.throttle = 0.0;
      d.controls.brake = 0.5;
    }
    apply(d);
  }
  // a bot lost (stuck, on its roof, off the track): respawned as a player's "R" is
  for (int v : bots_->lost()) respawnVehicle(v);
}

void Session::raceRespawn(const Request& r) {
  const ReplyTo to = replyTo(r);
  const std::int64_t v = -r.steps - 1;
  if (!race_) return reply(to, false, ErrorCode::BadRequest, "respawn: the session's scenario has no race");
  if (v < 0 || v >= race_->race.cars())
    return reply(to, false, ErrorCode::BadRequest,
                 "respawn: no vehicle " + std::to_string(v) + " (the session has " +
                     std::to_string(race_->race.cars()) + ")");
  if (status_ == Status::Diverged)
    return reply(to, false, ErrorCode::Diverged, "respawn: session diverged: " + reason_ + " (reset it)");
  respawnVehicle(static_cast<int>(v));
  reply(to, true, ErrorCode::None, "");
}

// Vehicle v back at its last gate (raceRespawnCar), logged as an applied
// entry (re-simulation and a standby's replay place it again by the same rule).
void Session::respawnVehicle(int v) {
  Applied a;
  a.kind = AppliedKind::Respawn;
  a.vehicle = v;
  logApplied(std::move(a));
  for (const race::RaceEvent& e : raceRespawnCar(*race_, sim_, initial_, v))
    event(Severity::Info, ErrorCode::None, race::Race::reason(e, setup_.vehicle_names));
  if (bots_) bots_->relocate(v, sim_.state().t);
  frame_pending_ = true;
}

}  // namespace groundsim::session
