// `groundsim drive` on a road car (scenario kind "road_car"): normalized
// controls (controls_t) from the keyboard or from script lines.
//
// A terminal sends key presses and never a release, so every pedal and the
// steering work as a target that a press raises and that falls back unless
// the key is pressed again: holding a key (the terminal's auto-repeat, ~30
// presses/s after ~0.5 s) holds the value, letting go returns it to zero
// kRelease s after the last press at kReturnRate per second.
#pragma once

#include <string>

#include <groundsim/controls_t.hpp>

#include "terminal.hpp"

namespace groundsim::cli {

struct CarIntent {
  static constexpr double kPedalStep = 0.2;   // throttle/brake per key press
  static constexpr double kSteerStep = 0.15;  // steer per key press
  static constexpr double kRelease = 0.6;     // s a value holds after its key's last press
  static constexpr double kReturnRate = 2.0;  // 1/s then back towards 0 (full scale in 0.5 s)

  double throttle = 0.0;  // [0, 1]
  double brake = 0.0;     // [0, 1]
  double steer = 0.0;     // [-1, 1], + = left
  bool handbrake = false;
  int gear = groundsim::controls_t::GEAR_AUTO;
  bool decays = false;    // keyboard values return to zero; script values hold
  // seconds since each value's key was last pressed
  double throttle_age = 0.0, brake_age = 0.0, steer_age = 0.0;

  // Advances the keyboard ramps by dt seconds (nothing for script values).
  void tick(double dt);
  groundsim::controls_t toMessage(const std::string& session, int vehicle) const;
  // "throttle 0.60 brake 0.00 steer +0.15 gear auto"
  std::string describe() const;
};

// Script line: throttle T | brake B | steer S | turn S | handbrake 0|1 |
// gear auto|r|n|1..n | release | wait S | quit. Values are sent as given
// (the server refuses NaN and out-of-range values, naming the field).
// Returns seconds to wait (0 none), < 0 to quit; throws invalid_argument.
double applyCarLine(const std::string& line, CarIntent& in);

// Keys: w/up throttle, s/down brake, a/left and d/right steer, space full
// brake, h handbrake (toggle), r reverse, n neutral, 0 automatic, 1..9
// manual gear, x release all, q quit. Returns false to quit.
bool applyCarKey(const KeyPress& k, CarIntent& in);

// "auto", "R", "N" or the gear number.
std::string gearName(int gear);

}  // namespace groundsim::cli
