// Small scenes shared by the physics tests, defined in code.
#pragma once

#include <numbers>

#include "physics/model_builder.hpp"
#include "physics/simulator.hpp"
#include "physics/vehicle.hpp"

namespace groundsim::test {

inline constexpr double kPi = std::numbers::pi;

// A ground far below everything: space.
inline GroundPtr farGround() { return makePlane(Vec3::UnitZ(), -1e6); }

inline Options spaceOptions(double dt) {
  Options o;
  o.dt = dt;
  o.gravity = Vec3::Zero();
  o.limits.max_speed = 1e9;
  return o;
}

// The report's car on flat ground, optionally in space.
inline BuiltModel reportCar(Options o, GroundPtr g, CarParams p = {}, CarPlacement at = {}) {
  ModelBuilder b(o, std::move(g));
  addCar(b, "car", p, at);
  return b.build();
}

inline double speedOf(const Simulator& s, int body = 0) { return bodyVel(s.state().y, body).norm(); }

}  // namespace groundsim::test
