// The validated `race` section (race_section.cpp): checkpoint gates along a
// track, laps, the start grid and the track's boundary. The race layer
// (server/race) times cars through it; docs/scenario.md defines each field.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace groundsim::scenario {

// A gate: the line from `left` to `right` (horizontal, world x y, m), as a
// driver going the right way sees its posts. Forward, the way it is to be
// crossed, is `right - left` turned a quarter left (counter-clockwise).
struct RaceGate {
  std::array<double, 2> left{0.0, 0.0}, right{0.0, 0.0};
};

// A start grid slot: the body centre's x y and heading (rad, 0: +x).
struct GridSlot {
  std::array<double, 2> position{0.0, 0.0};
  double yaw = 0.0;
};

struct RaceSpec {
  std::vector<RaceGate> gates;     // in order; gates[0] is the start (and, on a circuit, the finish) line
  int laps = 1;
  bool circuit = true;             // false: a stage from gates[0] to the last gate, laps = 1
  double countdown = 3.0;          // s   cars are held until the countdown ends ("go")
  std::vector<GridSlot> grid;      // vehicle k starts at grid[k] (when there is one)
  // off track: the body centre farther than half_width from the centre line
  // (a polyline, closed on a circuit); empty: never off track
  std::vector<std::array<double, 2>> centerline;
  double half_width = 0.0;         // m
  double respawn_protection = 3.0; // s   a respawned car passes through others this long
  double wrong_way_time = 1.0;     // s   moving against the track this long is "wrong way"
  // the last `bots` road cars are driven by the classical driver
  // (server/drivers, docs/drivers.md) in a session, through the players'
  // controls path and applied log
  int bots = 0;
  // the bots' driver: a trained policy file (drivers/policy.hpp, named
  // like a heightfield and sent with the scenario) instead of the
  // classical one; its text is read with the scenario
  std::string bot_policy;
  std::shared_ptr<const std::string> bot_policy_text;
  // the bots' difficulty in [0.2, 1]: their throttle is capped at it
  double bot_skill = 1.0;
};

// Limits of the section (each refused above, naming its field).
inline constexpr int kMaxRaceGates = 1000;
inline constexpr int kMaxRaceLaps = 1000;
inline constexpr int kMaxGridSlots = 64;
inline constexpr int kMaxCenterlinePoints = 10000;
// The largest bot policy file read with a scenario (drivers/policy.hpp).
inline constexpr std::size_t kMaxBotPolicyBytes = 16u << 20;

}  // namespace groundsim::scenario
