// The sedan of issue 9 (configs/sedan.json) and a variant with other
// figures, built in code, plus a driver loop for the tests.
#pragma once

#include <cmath>
#include <functional>
#include <numbers>
#include <ostream>
#include <string>
#include <utility>

#include "physics/build/road_car_builder.hpp"
#include "physics/road_car/steering.hpp"
#include "physics/simulator.hpp"
#include "physics/checks/telemetry.hpp"

namespace groundsim::test {

inline constexpr double kG = 9.81;
inline constexpr double kPi = std::numbers::pi;
inline constexpr double kPiRpm = std::numbers::pi / 30.0;  // rad/s per rpm

inline RoadCarParams sedan() {
  RoadCarParams p;  // the defaults are the sedan's figures
  p.suspension[0].ride_frequency = 1.3;
  p.suspension[1].ride_frequency = 1.4;
  p.tyre[0].cornering_stiffness = 6e4;
  p.tyre[1].cornering_stiffness = 8e4;
  return p;
}

// Other figures everywhere: a light, short, front-heavy hatchback.
inline RoadCarParams hatch() {
  RoadCarParams p = sedan();
  p.mass = 1100.0;
  p.inertia = Vec3(380.0, 1500.0, 1650.0);
  p.wheelbase = 2.45;
  p.cg_to_front = 0.95;
  p.cg_height = 0.50;
  p.track = 1.45;
  p.wheel_radius = 0.29;
  p.wheel_mass = 16.0;
  p.wheel_inertia = 0.7;
  p.suspension[0].ride_frequency = 1.6;
  p.suspension[1].ride_frequency = 1.75;
  p.suspension[0].damping_ratio = p.suspension[1].damping_ratio = 0.25;
  for (auto& t : p.tyre) t.vertical_stiffness = 1.8e5;
  p.tyre[0].cornering_stiffness = 5.5e4;
  p.tyre[1].cornering_stiffness = 5.0e4;
  p.powertrain.gears = {3.3, 1.9, 1.3, 0.97, 0.78};
  p.powertrain.final_drive = 4.1;
  for (double& t : p.powertrain.torque) t *= 0.7;
  p.aero.drag_area = 0.62;
  p.powertrain.drive = Drive::Front;
  p.brakes.max_torque = 5000.0;
  p.brakes.front_share = 0.72;
  p.tyre[0].rolling_resistance = p.tyre[1].rolling_resistance = 0.010;
  return p;
}

inline Options carOptions(double dt = 2e-3, double mu = 1.0) {
  Options o;
  o.dt = dt;
  o.gravity = Vec3(0, 0, -kG);
  o.contact.friction = mu;
  return o;
}

struct CarSim {
  std::unique_ptr<Simulator> sim;
  RoadCarParams p;
  const RoadCar& car() const { return sim->model().road_cars[0]; }
  Vec3 pos() const { return bodyPos(sim->state().y, car().body); }
  Vec3 vel() const { return bodyVel(sim->state().y, car().body); }
  Vec3 forward() const { return Quat(bodyRot(sim->state().y, car().body)).normalized() * Vec3::UnitX(); }
  double speed() const { return vel().dot(forward()); }
  VehicleSample sample() { return sampleVehicle(*sim, 0, false); }
  void set(const CarControls& c) { sim->setCarControls(0, c); }
  // steps until done(t) or t_max; false when the run diverged
  bool runUntil(double t_max, const std::function<bool()>& done = [] { return false; }) {
    while (sim->state().t < t_max - 1e-12) {
      if (!sim->step()) return false;
      if (done()) return true;
    }
    return true;
  }
};

inline CarSim makeCar(const RoadCarParams& p, const Options& o, double speed = 0.0, GroundPtr ground = nullptr,
                      double yaw = 0.0) {
  ModelBuilder b(o, ground ? ground : makePlane(Vec3::UnitZ(), 0.0));
  CarPlacement at;
  at.speed = speed;
  at.yaw = yaw;
  addRoadCar(b, "car", p, at);
  BuiltModel built = b.build();
  CarSim cs;
  cs.p = p;
  cs.sim = std::make_unique<Simulator>(built.model, built.initial);
  return cs;
}

// A car at `speed` (m/s) with the brake pedal fully down from t = 0.
inline CarSim brakingCar(const RoadCarParams& p, const Options& o, double speed, GroundPtr ground = nullptr) {
  CarSim cs = makeCar(p, o, speed, std::move(ground));
  CarControls c;
  c.brake = 1.0;
  cs.set(c);
  return cs;
}

// a named car for the suites parameterised over cars (gtest prints the name)
struct Car {
  std::string name;
  RoadCarParams p;
};
inline void PrintTo(const Car& c, std::ostream* os) { *os << c.name; }

}  // namespace groundsim::test
