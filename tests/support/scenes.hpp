// Small scenes shared by the tests and the benchmarks, defined in code: one
// definition of each, so a test and the accuracy sweep measure the same thing.
#pragma once

#include <cmath>
#include <numbers>

#include "physics/build/model_builder.hpp"
#include "physics/simulator.hpp"
#include "physics/build/vehicle.hpp"

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

// Two point masses joined by one spring-dashpot of rest length 1 along x:
// particle 0 at the origin, particle 1 at x = 1 + stretch. In space (no
// gravity, no ground) with options o as given; the relative coordinate is a
// damped oscillator of omega = sqrt(k / mu), mu = m1 m2 / (m1 + m2).
struct SpringPairSpec {
  double m1 = 1.0, m2 = 1.0;   // kg
  double stiffness = 100.0;    // N/m
  double damping = 0.0;        // N s/m
  double stretch = 0.1;        // m   initial
  Vec3 v1 = Vec3::Zero(), v2 = Vec3::Zero();  // m/s initial
  double omega() const { return std::sqrt(stiffness * (m1 + m2) / (m1 * m2)); }
};

inline BuiltModel springPair(Options o, const SpringPairSpec& p) {
  o.gravity = Vec3::Zero();
  ModelBuilder b(o, farGround());
  const int a = b.addParticle(p.m1, Vec3::Zero(), p.v1, false);
  const int c = b.addParticle(p.m2, Vec3(1.0 + p.stretch, 0, 0), p.v2, false);
  Spring sp;
  sp.a = a;
  sp.b = c;
  sp.stiffness = p.stiffness;
  sp.damping = p.damping;
  sp.rest_length = 1.0;
  b.addSpring(sp);
  return b.build();
}

// The stretch of a spring pair (particles 0 and 1 on x).
inline double pairStretch(const State& s) { return s.y[6] - s.y[0] - 1.0; }

// One point of mass m at height z0 above the plane z = 0, moving down at v0,
// without gravity: the penalty contact of stiffness S and damping ratio zeta
// (c = 2 zeta sqrt(S m)) is a clamped damped oscillator, and the point leaves
// with the restitution of that oscillator (physics-notes.md).
inline BuiltModel droppedPoint(Options o, double m, double z0, double v0, double S, double zeta) {
  o.gravity = Vec3::Zero();
  o.contact.stiffness = S;
  o.contact.damping = 2 * zeta * std::sqrt(S * m);
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  b.addParticle(m, Vec3(0, 0, z0), Vec3(0, 0, -v0));
  return b.build();
}

inline double speedOf(const Simulator& s, int body = 0) { return bodyVel(s.state().y, body).norm(); }

}  // namespace groundsim::test
