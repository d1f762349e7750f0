#include "drivers/classical_driver.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace groundsim::drivers {

ClassicalDriver::ClassicalDriver(const TrackLine& line, const SpeedProfile& profile, const CarGeometry& car,
                                 const DriverTuning& tuning)
    : line_(line), profile_(profile), car_(car), tune_(tuning) {}

Pedals ClassicalDriver::drive(const CarSense& car) {
  // 1. where the car is along the line
  const TrackLine::Where w = line_.locate(car.position, s_, 30.0);
  s_ = w.s;
  offset_ = w.offset;
  const double v = std::max(car.speed, 0.0);
  // 2. steering: pure pursuit of the line's point L_d ahead,
  //    delta = atan(2 L sin(alpha) / L_d), alpha its bearing off the heading
  const double ld = tune_.lookahead_min + tune_.lookahead_time * v;
  const Vec2 target = line_.pointAt(s_ + ld);
  const double dx = target[0] - car.position[0], dy = target[1] - car.position[1];
  const double alpha = std::remainder(std::atan2(dy, dx) - car.yaw, 2.0 * std::numbers::pi);
  const double reach = std::max(std::hypot(dx, dy), 1e-3);
  const double delta = std::atan(2.0 * car_.wheelbase * std::sin(alpha) / reach);
  Pedals p;
  p.steer = std::clamp(delta / car_.max_steer, -1.0, 1.0);
  // 3. pedals: the profile's speed a little ahead (what the car must be
  //    doing by the time the pedals act), throttle below it, brake above
  const double want = profile_.at(s_ + tune_.anticipation * v);
  const double e = want - v;
  if (e > tune_.deadband) p.throttle = std::clamp(tune_.throttle_gain * (e - tune_.deadband) + 0.2, 0.0, 1.0);
  else if (e < -tune_.deadband) p.brake = std::clamp(tune_.brake_gain * (-e - tune_.deadband), 0.0, 1.0);
  else p.throttle = 0.15;  // hold the speed against drag and rolling
  return p;
}

std::vector<Vec2> racingLine(const scenario::RaceSpec& race) {
  if (race.centerline.size() >= 3) return {race.centerline.begin(), race.centerline.end()};
  std::vector<Vec2> line;
  for (const scenario::RaceGate& g : race.gates)
    line.push_back({0.5 * (g.left[0] + g.right[0]), 0.5 * (g.left[1] + g.right[1])});
  return line;
}

}  // namespace groundsim::drivers
