#include "telemetry.hpp"

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
  out.wheel_count = k;
  return out;
}

}  // namespace groundsim
