#include "sample.hpp"

#include <algorithm>

namespace groundsim::net {

VehicleSample toSample(const groundsim::state_t& m, int vehicle) {
  const groundsim::vehicle_state_t& o = m.vehicles.at(vehicle);
  VehicleSample s;
  s.t = m.t;
  s.tick = m.tick;
  s.position = Vec3(o.position[0], o.position[1], o.position[2]);
  s.orientation = Quat(o.orientation[0], o.orientation[1], o.orientation[2], o.orientation[3]);
  s.velocity = Vec3(o.velocity[0], o.velocity[1], o.velocity[2]);
  s.angular_velocity = Vec3(o.angular_velocity[0], o.angular_velocity[1], o.angular_velocity[2]);
  s.speed = o.speed;
  s.wheel_count = std::clamp<int>(o.wheel_count, 0, 4);
  for (int k = 0; k < 4; ++k) {
    s.wheels[k].spin = o.wheel_spin[k];
    s.wheels[k].normal_force = o.normal_force[k];
    s.wheels[k].friction_force = o.friction_force[k];
    s.wheels[k].slip = o.slip[k];
    s.wheels[k].in_contact = o.in_contact[k];
  }
  s.energy = m.energy;
  s.health = static_cast<Health>(m.health);
  return s;
}

}  // namespace groundsim::net
