// Computer drivers in a race session (issue 39, docs/drivers.md): the
// classical driver, or a trained policy (race.bot_policy), at the wheel of
// the race's last `bots` road cars, each keeping the traffic rules
// (drivers/traffic.hpp: off the cars ahead, players' and bots'). Every control period each bot's
// command goes through Session::apply as a player's would (the same
// clamping, controls timeout and applied log), so a race with bots
// re-simulates bit for bit from its log without them, and a standby that
// resumes the session replays their commands as logged.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "drivers/driver.hpp"
#include "drivers/track_line.hpp"
#include "physics/simulator.hpp"
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
  // Each bot's command from its car's state (valid until the next call).
  // While the race holds the cars (`held`: its countdown) the drivers are
  // not asked (a car ahead that stands on the grid is not one to go round)
  // and every bot holds its brakes.
  const std::vector<Command>& drive(const Model& m, const State& s, bool held = false);
  // A car put elsewhere (a respawn, a reset): its bot finds it again.
  void relocate(int vehicle);
  void relocateAll();
  bool drives(int vehicle) const;

  RaceBots(const RaceBots&) = delete;
  RaceBots& operator=(const RaceBots&) = delete;

 private:
  RaceBots() = default;
  struct Bot {
    int vehicle = 0;
    std::unique_ptr<drivers::Driver> driver;
  };
  // what the classical drivers share (they hold references)
  std::unique_ptr<drivers::TrackLine> line_;
  std::unique_ptr<drivers::SpeedProfile> profile_;
  std::vector<Bot> bots_;
  std::vector<Command> commands_;
  std::int64_t period_ = 1;
  double skill_ = 1.0;
};

}  // namespace groundsim::session
