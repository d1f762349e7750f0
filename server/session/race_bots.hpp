// Computer drivers in a race session (issue 39, docs/drivers.md): the
// classical driver, or a trained policy (race.bot_policy), at the wheel of
// the race's last `bots` road cars, each keeping the traffic rules
// (drivers/traffic.hpp: off the cars ahead, players' and bots'). Every control period each bot's
// command goes through Session::apply as a player's would (the same
// clamping, controls timeout and applied log), so a race with bots
// re-simulates bit for bit from its log without them, and a standby that
// resumes the session replays their commands as logged. A bot whose car is
// stuck, on its roof, lost off the track or the wrong way, or has passed
// no gate for long (one missed) asks for a respawn as a player presses R
// (RaceBots::lost); the session applies it as a player's, logged.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "drivers/driver.hpp"
#include "drivers/track_line.hpp"
#include "drivers/traffic.hpp"
#include "physics/simulator.hpp"
#include "race/race.hpp"
#include "scenario/race_spec.hpp"

namespace groundsim::session {

class RaceBots {
 public:
  static constexpr double kControlPeriod = 0.02;  // s: the classical driver's 50 commands a second

  // Null when the race has no bots. `road_car[v]`: vehicle v's index among
  // the model's road cars (-1: not a road car, never a bot). Throws
  // scenario::ScenarioError at /race/bot_policy when the policy file is
  // not one a bot can drive with.
  static std::unique_ptr<RaceBots> make(const scenario::RaceSpec& race, const Model& m,
                                        const std::vector<int>& road_car);

  struct Command {
    int vehicle = 0;
    CarControls controls;
  };
  // Whether the bots act before step `tick` (one in every control period:
  // the classical driver's, or the policy's own from its training).
  bool due(std::int64_t tick) const { return tick % period_ == 0; }
  // Each bot's command from its car's state (valid until the next call),
  // keeping the race's respawn protections (a protected car has the way).
  // While the race holds the cars (its countdown) the drivers are not
  // asked (a car ahead that stands on the grid is not one to go round)
  // and every bot holds its brakes.
  const std::vector<Command>& drive(const Model& m, const State& s, const race::Race& race);
  // The bots' cars to respawn now (valid until the next call), judged at
  // each drive: below kStuckSpeed for kStuckFor, on the roof for
  // kFlippedFor, off the track or the wrong way for kLostFor, or no gate
  // for kNoGateFor since the last one or the start. Never while held,
  // protected or finished.
  static constexpr double kStuckSpeed = 0.5;  // m/s
  static constexpr double kStuckFor = 6.0;    // s
  static constexpr double kFlippedFor = 2.0;  // s
  static constexpr double kLostFor = 4.0;     // s
  static constexpr double kNoGateFor = 25.0;  // s
  const std::vector<int>& lost() const { return lost_; }
  // A car put elsewhere at time t (a respawn, a reset): its bot finds it
  // again, and its clocks for lost() start over.
  void relocate(int vehicle, double t);
  void relocateAll(double t);
  bool drives(int vehicle) const;

  RaceBots(const RaceBots&) = delete;
  RaceBots& operator=(const RaceBots&) = delete;

 private:
  RaceBots() = default;
  struct Bot {
    int vehicle = 0;
    int body = 0;
    std::unique_ptr<drivers::Driver> driver;
    drivers::TrafficAware* traffic = nullptr;  // driver's outer layer
    std::vector<int> others;                   // the vehicles of traffic's `others`, in its order
    double stuck = 0.0, flipped = 0.0, astray = 0.0;  // s so far
    double placed = 0.0;                              // s: put where it is then (a respawn)
    void restart(double t) {
      driver->relocate();
      stuck = flipped = astray = 0.0;
      placed = t;
    }
  };
  void judge(Bot& bot, const State& s, const race::Race& race, double dt);
  // what the classical drivers share (they hold references)
  std::unique_ptr<drivers::TrackLine> line_;
  std::unique_ptr<drivers::SpeedProfile> profile_;
  std::vector<Bot> bots_;
  std::vector<Command> commands_;
  std::vector<int> lost_;
  std::int64_t period_ = 1;
  double skill_ = 1.0;
};

}  // namespace groundsim::session
