// Free fall: symplectic Euler has a closed-form trajectory,
// z_n = z0 - g h^2 n (n + 1) / 2 = z0 - g (t^2 + h t) / 2,
// i.e. the exact parabola plus an error of exactly -g h t / 2.
#include <gtest/gtest.h>

#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

TEST(FreeFall, ParticleFollowsTheSymplecticEulerParabolaExactly) {
  const double h = 1e-3, g = 9.8, z0 = 100.0;
  Options o;
  o.dt = h;
  ModelBuilder b(o, farGround());
  b.addParticle(2.0, Vec3(0, 0, z0), Vec3(1.0, 0, 0));
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(1000));
  const double t = sim.state().t;
  const auto& y = sim.state().y;
  EXPECT_NEAR(y[2], z0 - 0.5 * g * (t * t + h * t), 1e-9);
  EXPECT_NEAR(y[0], 1.0 * t, 1e-12);            // no force sideways
  EXPECT_NEAR(y[5], -g * t, 1e-9);              // velocity is exact
}

TEST(FreeFall, RigidBodyCentreFallsLikeAPointAndDoesNotRotate) {
  const double h = 1e-3, g = 9.8;
  Options o;
  o.dt = h;
  ModelBuilder b(o, farGround());
  BodySpec s;
  s.name = "box";
  for (int i = 0; i < 8; ++i) {
    s.points.push_back(Vec3(i & 1 ? 1 : -1, i & 2 ? 0.5 : -0.5, i & 4 ? 0.2 : -0.2));
    s.masses.push_back(0.25);
    s.contact.push_back(true);
  }
  s.origin = Vec3(0, 0, 10);
  b.addBody(s);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(2000));
  const double t = sim.state().t;
  EXPECT_NEAR(bodyPos(sim.state().y, 0).z(), 10 - 0.5 * g * (t * t + h * t), 1e-9);
  EXPECT_NEAR(Quat(bodyRot(sim.state().y, 0)).angularDistance(Quat::Identity()), 0.0, 1e-12);
}

TEST(FreeFall, ErrorIsFirstOrderInTheStep) {
  // e(h) = g h t / 2: halving h halves the error (order p = 1)
  auto error = [](double h) {
    Options o;
    o.dt = h;
    ModelBuilder b(o, farGround());
    b.addParticle(1.0, Vec3::Zero(), Vec3::Zero());
    auto built = b.build();
    Simulator sim(built.model, built.initial);
    sim.step(static_cast<long long>(std::llround(1.0 / h)));
    return std::abs(sim.state().y[2] - (-0.5 * 9.8));
  };
  const double p = std::log2(error(1e-2) / error(5e-3));
  EXPECT_NEAR(p, 1.0, 1e-6);
}
