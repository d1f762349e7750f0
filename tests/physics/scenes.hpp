// Small scenes shared by the physics tests, defined in code.
#pragma once

#include <cmath>
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

// A thin hoop of n points about the y axis (I = m r^2 about y, m r^2 / 2
// about diameters).
inline BodySpec hoop(int n, double r, double m) {
  BodySpec s;
  s.name = "hoop";
  for (int k = 0; k < n; ++k) {
    const double phi = 2 * kPi * k / n;
    s.points.push_back(Vec3(r * std::cos(phi), 0, r * std::sin(phi)));
    s.masses.push_back(m / n);
    s.contact.push_back(false);
  }
  return s;
}

// The report's car on flat ground, optionally in space.
inline BuiltModel reportCar(Options o, GroundPtr g, CarParams p = {}, CarPlacement at = {}) {
  ModelBuilder b(o, std::move(g));
  addCar(b, "car", p, at);
  return b.build();
}

inline double speedOf(const Simulator& s, int body = 0) { return bodyVel(s.state().y, body).norm(); }

}  // namespace groundsim::test
