// The classical driver (docs/drivers.md), the baseline a trained driver's
// lap is judged against, as TORCS robots are built: pure pursuit on the
// track's centre line for the steering, a speed profile from the line's
// curvature and the car's grip for the pedals.
#pragma once

#include <vector>

#include "drivers/track_line.hpp"
#include "scenario/race_spec.hpp"

namespace groundsim::drivers {

// What the driver senses of its car: where it is, which way it points and
// how fast it goes forward.
struct CarSense {
  Vec2 position{0.0, 0.0};  // m    body centre, world x y
  double yaw = 0.0;         // rad  heading of the body's forward axis (0: +x)
  double speed = 0.0;       // m/s  along that axis
};

// Its commands, in the road car's units (CarControls): throttle and brake
// in [0, 1] (never both), steer in [-1, 1], + = left.
struct Pedals {
  double throttle = 0.0, brake = 0.0, steer = 0.0;
  bool reverse = false;  // in reverse gear (the traffic rules back out from behind a stopped car)
};

// The car as the driver knows it.
struct CarGeometry {
  double wheelbase = 2.7;   // m
  double max_steer = 0.61;  // rad  mean front road-wheel angle at steer 1
};

struct DriverTuning {
  double lookahead_min = 6.0;    // m    pure pursuit's look-ahead at standstill
  double lookahead_time = 0.5;   // s    and its growth with speed: L_d = min + time v
  double anticipation = 0.3;     // s    the profile is read this far ahead of the car
  double throttle_gain = 0.4;    // per m/s below the profile's speed
  double brake_gain = 0.25;      // per m/s above it
  double deadband = 0.3;         // m/s  neither pedal within it
};

class ClassicalDriver {
 public:
  // `line` and `profile` are kept by reference and must outlive the driver.
  ClassicalDriver(const TrackLine& line, const SpeedProfile& profile, const CarGeometry& car,
                  const DriverTuning& tuning = {});
  Pedals drive(const CarSense& car);
  // Where the last call found the car along the line, and off it (m).
  double along() const { return s_; }
  double offset() const { return offset_; }
  // A car put elsewhere (a respawn): the next call searches the whole line.
  void relocate() { s_ = -1.0; }

 private:
  const TrackLine& line_;
  const SpeedProfile& profile_;
  CarGeometry car_;
  DriverTuning tune_;
  double s_ = -1.0, offset_ = 0.0;
};

// The line a driver follows on a race: the track's centre line when it has
// bends (3 points or more), else the gates' centres in order (a stage along
// a straight line has nothing else to say where to drive).
std::vector<Vec2> racingLine(const scenario::RaceSpec& race);

}  // namespace groundsim::drivers
