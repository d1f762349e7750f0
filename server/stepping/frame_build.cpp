#include "stepping/frame_build.hpp"

#include <cmath>

#include "physics/checks/telemetry.hpp"

namespace groundsim::stepping {
namespace {

// A diverged simulator keeps its last finite state, but the workspace of the
// failed evaluation (contact forces, slip) may hold NaN: never publish it.
void finite(double& x) {
  if (!std::isfinite(x)) x = 0.0;
}
void sanitize(VehicleSample& s) {
  finite(s.t);
  finite(s.speed);
  finite(s.energy);
  for (int i = 0; i < 3; ++i) {
    finite(s.position[i]);
    finite(s.velocity[i]);
    finite(s.angular_velocity[i]);
  }
  if (!s.orientation.coeffs().allFinite()) s.orientation = Quat::Identity();
  for (auto& w : s.wheels) {
    finite(w.spin);
    finite(w.normal_force);
    finite(w.friction_force);
    finite(w.slip);
  }
}

}  // namespace

std::vector<VehicleWheels> vehicleWheels(const Model& m) {
  std::vector<VehicleWheels> vehicles(m.vehicle_names.size());
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const int v = m.vehicle_of_wheel[w];
    if (v < 0 || v >= static_cast<int>(vehicles.size())) continue;
    vehicles[v].wheels.push_back(static_cast<int>(w));
    vehicles[v].max_steer.push_back(m.wheels[w].steerable ? m.wheels[w].max_steer : 0.0);
  }
  for (size_t c = 0; c < m.road_cars.size(); ++c) {
    const int v = m.road_cars[c].vehicle;
    if (v < 0 || v >= static_cast<int>(vehicles.size())) continue;
    vehicles[v].road_car = static_cast<int>(c);
    vehicles[v].gears = static_cast<int>(m.road_cars[c].p.powertrain.gears.size());
  }
  return vehicles;
}

void fillFrame(Frame& f, const Simulator& sim, const std::vector<VehicleWheels>& vehicles) {
  const State& s = sim.state();
  f.t = s.t;
  f.tick = s.tick;
  f.health = s.health;
  f.vehicles.reserve(vehicles.size());
  for (size_t v = 0; v < vehicles.size(); ++v) {
    f.vehicles.push_back(sampleVehicle(sim, static_cast<int>(v), v == 0));
    sanitize(f.vehicles.back());
    const int c = vehicles[v].road_car;
    if (c >= 0) f.cars.push_back(CarFrame{static_cast<int>(v), s.car_controls.at(c), s.cars.at(c)});
  }
  const Model& m = sim.model();
  if (m.collisions || !m.objects.empty()) {
    f.contacts = true;
    f.model = sim.modelPtr();
    f.hits = sim.hits();
    for (size_t i = 0; i < m.objects.size(); ++i) {
      const SceneObject& o = m.objects[i];
      if (o.body < 0) continue;
      ObjectSample os;
      os.object = static_cast<int>(i);
      const Quat q = Quat(bodyRot(s.y, o.body)).normalized();
      os.position = Vec3(bodyPos(s.y, o.body)) + q * o.pos;
      os.orientation = q * Quat(o.rot);
      os.velocity = bodyVel(s.y, o.body);
      os.angular_velocity = angularVelocity(m, s, o.body);
      if (os.position.allFinite() && os.orientation.coeffs().allFinite() && os.velocity.allFinite() &&
          os.angular_velocity.allFinite())
        f.objects.push_back(os);
    }
  }
  if (!f.vehicles.empty()) f.energy = f.vehicles.front().energy;
  for (auto& v : f.vehicles) v.energy = f.energy;
}

}  // namespace groundsim::stepping
