// Races (docs/front-end.md, Races): a scenario's `race` section timed over a
// session's steps. Given each car's horizontal position at the start and
// end of every step, a Race holds the cars until the countdown ends, finds
// gate crossings by segment intersection (the crossing instant interpolated
// within the step, in simulated time), counts laps and splits, says when a
// car goes the wrong way or leaves the track, finishes cars and keeps the
// leaderboard. It knows nothing of physics or sessions: the session glue
// (server/stepping/race_glue.cpp) feeds it positions and publishes what it
// returns.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "scenario/race_spec.hpp"

namespace groundsim::race {

using Vec2 = std::array<double, 2>;

enum class EventKind {
  Go,        // the countdown ended at t: cars are released
  Start,     // a car crossed the start line (gates[0]) for the first time: its first lap starts at t
  Gate,      // a car crossed gate `gate` of lap `lap`; `time`: the split, since its lap started
  Lap,       // a car completed lap `lap` at t; `time`: the lap time; `best`: its best so far
  Finish,    // a car finished at t; `time`: since go; `position`: its place
  WrongWay,  // `on`: the car goes (true) / stopped going (false) against the track
  OffTrack,  // `on`: the car left (true) / came back to (false) the track
  Respawn,   // the car was put back at gate `gate` (-1: its grid slot); protected until `time`
};
const char* kindName(EventKind k);

struct RaceEvent {
  EventKind kind = EventKind::Go;
  int car = -1;
  double t = 0.0;       // s, simulated: the crossing instant for Start, Gate, Lap, Finish
  int gate = -1;
  int lap = 0;          // 1-based lap the event belongs to
  double time = 0.0;    // s: split, lap time or race time (see the kind)
  bool best = false;
  bool on = false;
  int position = 0;
};

// One car's standing.
struct CarStanding {
  int car = 0;
  int position = 0;          // 1-based place on the leaderboard
  bool started = false;      // crossed the start line
  bool finished = false;
  int laps_done = 0;
  int next_gate = 0;
  double lap_start = 0.0;    // s: the current lap started then (when started)
  double last_lap = 0.0;     // s, 0: none yet
  double best_lap = 0.0;     // s, 0: none yet
  double finish_time = 0.0;  // s since go (when finished)
  double last_cross = 0.0;   // s: the last gate crossing
  std::vector<double> splits;       // this lap's splits so far (gate 1, 2, ...)
  std::vector<double> best_splits;  // the best lap's splits
  bool wrong_way = false;
  bool off_track = false;
  double protected_until = 0.0;     // s: respawn protection
};

// Where a respawned car goes: x, y (the ground's height is the caller's) and heading.
struct Pose {
  Vec2 position{0.0, 0.0};
  double yaw = 0.0;
  int gate = -1;  // the gate it is put after; -1: its grid slot
};

// Whether segment p0 -> p1 crosses gate a -> b: the fraction s in [0, 1) of
// the way from p0 where it does (written to *s) and the direction: +1 the
// right way (along rot90(b - a)), -1 the wrong way; 0: no crossing.
int crossing(const Vec2& p0, const Vec2& p1, const Vec2& a, const Vec2& b, double* s);

class Race {
 public:
  Race(scenario::RaceSpec spec, int cars);

  const scenario::RaceSpec& spec() const { return spec_; }
  int cars() const { return static_cast<int>(cars_.size()); }
  // Back to the countdown (a session's reset).
  void reset();
  double goTime() const { return spec_.countdown; }
  // Cars are held (no throttle, brakes on) before go.
  bool held(double t) const { return t < spec_.countdown; }
  bool over() const;

  // One step from t0 to t1: before[k] and after[k] are car k's body centre
  // (x, y) then. Returns what happened, in time order within each car.
  std::vector<RaceEvent> step(double t0, double t1, const std::vector<Vec2>& before, const std::vector<Vec2>& after);

  // Where car k respawns: after the last gate it passed, or its grid slot
  // (nullopt: the race has no grid and the car passed no gate).
  std::optional<Pose> respawnPose(int car) const;
  // The car was put back at t: its wrong-way and off-track notices end.
  std::vector<RaceEvent> respawned(int car, const Pose& at, double t);
  bool isProtected(int car, double t) const { return t < cars_.at(static_cast<std::size_t>(car)).protected_until; }
  // Its protection lasts until `until` (the session keeps a car that is
  // still inside another protected until it is clear).
  void extendProtection(int car, double until) { cars_.at(static_cast<std::size_t>(car)).protected_until = until; }

  const CarStanding& standing(int car) const { return cars_.at(static_cast<std::size_t>(car)); }
  // Every car, leaderboard order: finished by finish time, then by laps
  // and gates passed, then by who got there first.
  std::vector<CarStanding> leaderboard() const;

  // The race's progress (every car's standing, the wrong-way clocks, who
  // finished, whether it went) as JSON, and back: a session's snapshot
  // carries it, so a standby that takes the session over keeps every
  // player's laps (docs/fleet.md). restore returns "" or why not.
  nlohmann::json progress() const;
  std::string restore(const nlohmann::json& progress);
  // "race: {json}" reasons for event_t (docs/protocol.md, Race events).
  static std::string reason(const RaceEvent& e, const std::vector<std::string>& names);
  std::string standingsReason(double t, const std::vector<std::string>& names) const;
  // The race's layout for a page: gates, laps, circuit, countdown, centre line.
  std::string layoutReason(const std::vector<std::string>& names) const;

 private:
  void cross(int k, int gate, double tc, std::vector<RaceEvent>& out);
  void wrongWay(int k, const Vec2& p0, const Vec2& p1, double t0, double t1, std::vector<RaceEvent>& out);
  void offTrack(int k, const Vec2& p, double t, std::vector<RaceEvent>& out);
  Vec2 gateCentre(int g) const;
  Vec2 gateForward(int g) const;  // unit
  double distanceToCentreline(int k, const Vec2& p);

  scenario::RaceSpec spec_;
  std::vector<CarStanding> cars_;
  std::vector<double> against_;   // per car: s moving against the track so far
  std::vector<int> near_segment_; // per car: the centre line's segment last found nearest
  int finished_ = 0;
  bool went_ = false;
};

}  // namespace groundsim::race
