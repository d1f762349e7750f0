#include "bridge/controls.hpp"

#include <algorithm>

namespace groundsim::web {

groundsim::drive_t toDrive(const Controls& c, int vehicle, int wheels, const ControlScale& scale) {
  groundsim::drive_t d{};
  d.vehicle = vehicle;
  d.nwheels = static_cast<int8_t>(wheels);
  d.drive_torque.assign(wheels, 0.0);
  d.brake_torque.assign(wheels, 0.0);
  d.steer.assign(wheels, 0.0);
  const double gear = c.gear > 0 ? 1.0 : c.gear < 0 ? -1.0 : 0.0;
  for (int k = 0; k < wheels; ++k) {
    const bool front = wheels == 1 || k < 2;
    d.drive_torque[k] = gear * std::clamp(c.throttle, 0.0, 1.0) * scale.drive_torque;
    double brake = std::clamp(c.brake, 0.0, 1.0);
    if (c.handbrake && (!front || wheels == 1)) brake = 1.0;
    d.brake_torque[k] = brake * scale.brake_torque;
    d.steer[k] = front && wheels > 1 ? std::clamp(c.steer, -1.0, 1.0) * scale.steer : 0.0;
  }
  return d;
}

groundsim::controls_t toCarControls(const Controls& c, int vehicle) {
  groundsim::controls_t m{};
  m.vehicle = vehicle;
  // NaN fails every comparison: std::clamp would pass it through
  auto clamp = [](double x, double lo, double hi) { return x >= lo ? (x <= hi ? x : hi) : lo; };
  m.throttle = clamp(c.throttle, 0.0, 1.0);
  m.brake = clamp(c.brake, 0.0, 1.0);
  m.steer = clamp(c.steer, -1.0, 1.0);
  m.handbrake = c.handbrake;
  m.gear = c.gear > 0 ? groundsim::controls_t::GEAR_AUTO
           : c.gear < 0 ? groundsim::controls_t::GEAR_REVERSE
                        : groundsim::controls_t::GEAR_NEUTRAL;
  return m;
}

}  // namespace groundsim::web
