#include "physics/checks/telemetry.hpp"

#include <cmath>

namespace groundsim {

VehicleSample sampleVehicle(const Simulator& sim, int vehicle, bool with_energy) {
  const Model& m = sim.model();
  VehicleSample out;
  if (with_energy) out.energy = sim.energy().total();
  const State& s = sim.state();
  const Workspace& ws = sim.workspace();
  const int b = m.vehicle_body.at(vehicle);
  out.t = s.t;
  out.tick = s.tick;
  out.position = bodyPos(s.y, b);
  out.orientation = Quat(bodyRot(s.y, b)).normalized();
  out.velocity = bodyVel(s.y, b);
  out.angular_velocity = angularVelocity(m, s, b);
  out.speed = out.velocity.norm();
  out.health = s.health;
  int k = 0;
  for (size_t w = 0; w < m.wheels.size() && k < 4; ++w) {
    if (m.vehicle_of_wheel[w] != vehicle) continue;
    const Wheel& wh = m.wheels[w];
    const Vec3 axis = Quat(bodyRot(s.y, wh.body)).normalized() * wh.axis;
    WheelSample& ws_out = out.wheels[k++];
    const Vec3 carrier = wh.carrier >= 0 ? angularVelocity(m, s, wh.carrier) : Vec3::Zero();
    ws_out.spin = axis.dot(angularVelocity(m, s, wh.body) - carrier);
    ws_out.normal_force = ws.wheel_normal[w];
    ws_out.friction_force = ws.wheel_friction[w];
    ws_out.slip = ws.wheel_slip[w];
    ws_out.in_contact = ws.wheel_normal[w] > 0.0;
  }
  out.yaw_rate = angularVelocity(m, s, b).dot(Quat(bodyRot(s.y, b)).normalized() * Vec3::UnitZ());
  const int c = sim.roadCarIndex(vehicle);
  if (c >= 0) {
    const RoadCar& rc = m.road_cars[static_cast<size_t>(c)];
    const RoadCarOut& ro = ws.road[static_cast<size_t>(c)];
    out.gear = s.cars[static_cast<size_t>(c)].gear;
    out.engine_rpm = ro.engine_rpm;
    out.drive_power = ro.drive_power;
    for (int w = 0; w < 4; ++w) {
      WheelSample& o = out.wheels[static_cast<size_t>(w)];
      const RoadWheelOut& rw = ro.wheel[static_cast<size_t>(w)];
      o.spin = s.y[m.auxBase() + rc.aux + roadAux(w, 2)];
      o.normal_force = rw.normal;
      o.friction_force = std::hypot(rw.fx, rw.fy);
      o.slip = std::abs(rw.slip_ratio);
      o.in_contact = rw.contact;
      o.slip_ratio = rw.slip_ratio;
      o.slip_angle = rw.slipAngle();
      o.travel = rw.travel;
    }
    k = 4;
  }
  out.wheel_count = k;
  return out;
}

}  // namespace groundsim
