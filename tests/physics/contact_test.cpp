// Ground contact against closed-form answers: static sag, bounce
// restitution, skid stop, and a parked car that must not creep.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "physics/checks/diagnostics.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

BodySpec slab(double mass, double z) {
  BodySpec s;
  s.name = "slab";
  for (int i = 0; i < 4; ++i) {  // four contact feet at the bottom corners
    s.points.push_back(Vec3(i & 1 ? 1.0 : -1.0, i & 2 ? 0.5 : -0.5, -0.2));
    s.masses.push_back(mass / 8);
    s.contact.push_back(true);
    s.points.push_back(Vec3(i & 1 ? 1.0 : -1.0, i & 2 ? 0.5 : -0.5, 0.2));
    s.masses.push_back(mass / 8);
    s.contact.push_back(false);
  }
  s.origin = Vec3(0, 0, z);
  return s;
}

}  // namespace

TEST(Contact, StaticSagIsWeightOverTotalStiffness) {
  Options o;
  o.dt = 1e-4;
  o.contact.stiffness = 5000.0;
  const double M = 2.0;
  o.contact.damping = 2.0 * 0.7 * std::sqrt(o.contact.stiffness * M / 4);  // settles fast
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  b.addBody(slab(M, 0.2));
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(30000));
  const double sag = 0.2 - bodyPos(sim.state().y, 0).z();
  EXPECT_NEAR(sag, M * 9.8 / (4 * o.contact.stiffness), 1e-9);
}

TEST(Contact, BounceRestitutionMatchesTheDampedOscillator) {
  // In contact a point on a Kelvin-Voigt ground is a damped oscillator,
  // depth d(t) = (v0 / wd) exp(-zeta w t) sin(wd t). The ground lets go when
  // its force S d + c d' reaches zero (it never pulls), and with no gravity
  // the point leaves with the velocity it has then.
  const double S = 1e4, m = 0.5, v0 = 1.0;
  for (double zeta : {0.05, 0.3}) {
    Options o;
    o.dt = 1e-6;
    auto built = droppedPoint(o, m, 0.001, v0, S, zeta);
    Simulator sim(built.model, built.initial);
    while (sim.state().t < 1.0 && !(sim.state().y[2] > 0.0015)) sim.step();
    const double v_out = sim.state().y[5];

    const double w = std::sqrt(S / m), wd = w * std::sqrt(1 - zeta * zeta), c = 2 * zeta * std::sqrt(S * m);
    auto depth = [&](double t) { return v0 / wd * std::exp(-zeta * w * t) * std::sin(wd * t); };
    auto rate = [&](double t) {
      return v0 / wd * std::exp(-zeta * w * t) * (wd * std::cos(wd * t) - zeta * w * std::sin(wd * t));
    };
    double lo = 0.5 * kPi / wd, hi = kPi / wd;  // force changes sign in here
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (S * depth(mid) + c * rate(mid) > 0 ? lo : hi) = mid;
    }
    const double e = -rate(lo) / v0;
    EXPECT_NEAR(v_out / v0, e, 2e-3 * e) << "zeta " << zeta;
    // the textbook exp(-pi zeta / sqrt(1 - zeta^2)) ignores the clamp: lower
    EXPECT_GT(e, std::exp(-kPi * zeta / std::sqrt(1 - zeta * zeta)));
  }
}

TEST(Contact, SkidStopsAtVSquaredOverTwoMuG) {
  Options o;
  o.dt = 1e-4;
  o.contact.stiffness = 1e5;
  o.contact.damping = 2.0 * std::sqrt(1e5 * 0.25);
  o.contact.friction = 0.5;
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  BodySpec s = slab(1.0, 0.2 - 9.8 / 4e5);  // resting at its static sag
  s.velocity = Vec3(5.0, 0, 0);
  b.addBody(s);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  while (bodyVel(sim.state().y, 0).x() > 0 && sim.state().t < 5) sim.step();
  const double d = bodyPos(sim.state().y, 0).x();
  const double expected = 25.0 / (2 * 0.5 * 9.8);
  EXPECT_NEAR(d, expected, 0.01 * expected);
  // once stopped it stays stopped: static friction holds with no chatter
  // (after the pitch the braking torque caused has relaxed, about 0.5 s)
  sim.step(5000);
  const double x_rest = bodyPos(sim.state().y, 0).x();
  EXPECT_NEAR(x_rest, d, 1e-5);
  sim.step(20000);
  EXPECT_NEAR(bodyPos(sim.state().y, 0).x(), x_rest, 1e-9);
}

TEST(Contact, ParkedCarOnTwentyDegreesDoesNotCreep) {
  for (double dt : {5e-5, 2e-4}) {
    Options o;
    o.dt = dt;
    o.contact.friction = 0.9;
    o.contact.damping = 20.0;
    auto built = reportCar(o, makeIncline(20 * kPi / 180, Vec3::UnitX()));
    Simulator sim(built.model, built.initial);
    for (auto& c : sim.controls()) c.brake_torque = 10.0;
    ASSERT_TRUE(sim.step(static_cast<long long>(3.0 / dt)));  // settle
    const Vec3 x0 = bodyPos(sim.state().y, 0);
    ASSERT_TRUE(sim.step(static_cast<long long>(10.0 / dt)));
    EXPECT_LT((bodyPos(sim.state().y, 0) - x0).norm(), 1e-6) << "dt " << dt;
  }
}

TEST(Contact, SignFrictionOfTheReportCreepsWhereStickSlipHolds) {
  // the contrast that motivates stick-slip: same car, same slope
  Options o;
  o.dt = 5e-5;
  o.contact.friction = 0.9;
  o.contact.damping = 20.0;
  o.contact.friction_model = FrictionModel::Sign;
  auto built = reportCar(o, makeIncline(20 * kPi / 180, Vec3::UnitX()));
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.brake_torque = 10.0;
  sim.step(60000);
  const Vec3 x0 = bodyPos(sim.state().y, 0);
  sim.step(100000);
  EXPECT_GT((bodyPos(sim.state().y, 0) - x0).norm(), 1e-5);
}

TEST(Contact, BroadPhaseSkipsOnlyWhatCannotTouchAndChangesNoResult) {
  // a car jumping over bumps: wheels and body are often provably clear of
  // the ground; skipping them must give bit-identical states
  auto run = [](bool broad) {
    Options o;
    o.dt = 1e-4;
    o.broad_phase = broad;
    o.contact.damping = 20.0;
    CarPlacement at;
    at.position = Vec3(0, 0, 0);
    at.clearance = 0.5;  // dropped from half a metre
    at.speed = 3.0;
    at.wheel_spin = 3.0;
    auto built = reportCar(o, makeSinSinBumps(0.3, 4.0, 6.0), {}, at);
    Simulator sim(built.model, built.initial);
    long long skipped = 0;
    for (int i = 0; i < 20000; ++i) {
      sim.step();
      for (unsigned char far : sim.workspace().body_far) skipped += far;
    }
    return std::make_pair(sim.state().y, skipped);
  };
  const auto [with, skipped] = run(true);
  const auto [without, none] = run(false);
  EXPECT_GT(skipped, 1000);  // the broad phase did skip work
  EXPECT_EQ(none, 0);
  ASSERT_EQ(with.size(), without.size());
  EXPECT_EQ(0, std::memcmp(with.data(), without.data(), sizeof(double) * with.size()));
}
