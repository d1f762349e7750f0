// Once per step (the adaptive integrator: once per substep): commanded
// controls -> what the wheels and road cars apply (clamped, steering at its
// rate, the gear).
#include "physics/forces/controls.hpp"

#include <algorithm>
#include <cmath>

#include "physics/forces/road_car_phase.hpp"
#include "physics/road_car/steering.hpp"

namespace groundsim {
namespace {
double unit(double v, double lo) { return std::isfinite(v) ? std::clamp(v, lo, 1.0) : 0.0; }
}  // namespace

void applyRoadCarControls(const Model& m, double dt, State& s) {
  const int base = m.auxBase();
  for (size_t c = 0; c < m.road_cars.size(); ++c) {
    const RoadCar& rc = m.road_cars[c];
    const RoadCarParams& p = rc.p;
    const CarControls& cmd = s.car_controls[c];
    CarRuntime& rt = s.cars[c];
    rt.applied = cmd;
    rt.applied.throttle = unit(cmd.throttle, 0.0);
    rt.applied.brake = unit(cmd.brake, 0.0);
    rt.applied.steer = unit(cmd.steer, -1.0);
    for (double& t : rt.applied.wheel_torque)
      if (!std::isfinite(t)) t = 0.0;
    const double target = rt.applied.steer * p.steering.max_angle, most = p.steering.rate * dt;
    rt.steer_angle += std::clamp(target - rt.steer_angle, -most, most);

    const int n = static_cast<int>(p.powertrain.gears.size());
    rt.since_shift += dt;
    if (cmd.gear == CarControls::kNeutral) {
      rt.gear = 0;
    } else if (cmd.gear == CarControls::kReverse) {
      rt.gear = -1;
    } else if (cmd.gear >= 1) {
      rt.gear = std::min(cmd.gear, std::max(n, 1));
    } else if (rt.gear <= 0) {
      rt.gear = 1;
      rt.since_shift = 0.0;
    } else if (rt.since_shift >= p.powertrain.shift_interval) {
      const bool fd = p.powertrain.drive != Drive::Rear, rd = p.powertrain.drive != Drive::Front;
      double wsum = 0.0;
      int nd = 0;
      for (int w = 0; w < 4; ++w)
        if ((w < 2 && fd) || (w >= 2 && rd)) {
          wsum += s.y[base + rc.aux + roadAux(w, 2)];
          ++nd;
        }
      const int g = automaticGear(p.powertrain, rt.applied.throttle, nd ? wsum / nd : 0.0);
      if (g != rt.gear) {
        rt.gear = g;
        rt.since_shift = 0.0;
      }
    }
  }
}

void applyControls(const Model& m, double dt, State& s) {
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const Wheel& wh = m.wheels[w];
    const WheelControl& c = s.controls[w];
    WheelControl& a = s.applied[w];
    a.drive_torque = std::isfinite(c.drive_torque) ? c.drive_torque : 0.0;
    a.brake_torque = std::isfinite(c.brake_torque) ? std::max(c.brake_torque, 0.0) : 0.0;
    const double target = wh.steerable && std::isfinite(c.steer)
                              ? std::clamp(c.steer, -wh.max_steer, wh.max_steer)
                              : 0.0;
    const double most = wh.steer_rate * dt;
    a.steer += std::clamp(target - a.steer, -most, most);
  }
  applyRoadCarControls(m, dt, s);
}

bool controlsMoved(const std::vector<WheelControl>& applied, const std::vector<CarRuntime>& cars, const State& s) {
  for (size_t w = 0; w < s.applied.size(); ++w)
    if (s.applied[w].steer != applied[w].steer) return true;
  for (size_t c = 0; c < s.cars.size(); ++c)
    if (s.cars[c].steer_angle != cars[c].steer_angle || s.cars[c].gear != cars[c].gear) return true;
  return false;
}

}  // namespace groundsim
