// Every integrator against closed-form answers: order of convergence on a
// spring, a free symmetric top's precession (orientation, not only the
// conserved quantities), drive-work bookkeeping, force-evaluation counts,
// bit-exact save/restore and no allocation per step.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "physics/checks/diagnostics.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

const IntegratorKind kAll[] = {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet,
                               IntegratorKind::Rk4, IntegratorKind::ImplicitEuler, IntegratorKind::Adaptive};

std::string kindName(const testing::TestParamInfo<IntegratorKind>& info) { return integratorName(info.param); }

// Two unit masses on a spring k = 100 (omega = sqrt(k (m1 + m2) / (m1 m2)) =
// sqrt(200)), stretched by s0 and released: the stretch is s0 cos(omega t).
// Error at T: |stretch error| / s0 + |rate error| / (omega s0).
double springError(IntegratorKind kind, double h, double T, double tol = 1e-6) {
  const double k = 100.0, s0 = 0.1, omega = std::sqrt(200.0);
  Options o = spaceOptions(h);
  o.integrator = kind;
  o.tolerance = tol;
  SpringPairSpec pair;
  pair.stiffness = k;
  pair.stretch = s0;
  auto built = springPair(o, pair);
  Simulator sim(built.model, built.initial);
  EXPECT_TRUE(sim.step(std::llround(T / h)));
  const auto& y = sim.state().y;
  const double t = sim.state().t;
  const double stretch = y[6] - y[0] - 1.0, rate = y[9] - y[3];
  return std::abs(stretch - s0 * std::cos(omega * t)) / s0 +
         std::abs(rate + s0 * omega * std::sin(omega * t)) / (omega * s0);
}

struct OrderCase {
  IntegratorKind kind;
  double h;       // coarse step; the fine one is h / 2
  double order;   // theoretical order
};

class ConvergenceOrder : public testing::TestWithParam<OrderCase> {};

TEST_P(ConvergenceOrder, MatchesTheoryOnASpring) {
  const OrderCase c = GetParam();
  // the mean of three step pairs smooths the oscillation of the error's
  // phase with h
  double sum = 0.0;
  for (double h : {c.h, 0.8 * c.h, 0.64 * c.h}) {
    const double coarse = springError(c.kind, h, 1.0), fine = springError(c.kind, h / 2, 1.0);
    sum += std::log2(coarse / fine);
  }
  EXPECT_NEAR(sum / 3.0, c.order, 0.15) << integratorName(c.kind);
}

INSTANTIATE_TEST_SUITE_P(Integrators, ConvergenceOrder,
                         testing::Values(OrderCase{IntegratorKind::SemiImplicitEuler, 2e-3, 1.0},
                                         OrderCase{IntegratorKind::VelocityVerlet, 1e-2, 2.0},
                                         OrderCase{IntegratorKind::Rk4, 2e-2, 4.0},
                                         OrderCase{IntegratorKind::ImplicitEuler, 1e-3, 1.0}),
                         [](const auto& info) { return std::string(integratorName(info.param.kind)); });

TEST(Adaptive, GlobalErrorFollowsTheTolerance) {
  // output step 0.05 s (omega h = 0.7): the tolerance, not dt, sets the error
  double previous = 1.0;
  for (double tol : {1e-4, 1e-6, 1e-8}) {
    // springError is relative to the 0.1 m amplitude; the tolerance is
    // absolute (metres, m/s) for components below 1: the global error over
    // 2.2 periods stays within a modest multiple of it
    const double e = 0.1 * springError(IntegratorKind::Adaptive, 0.05, 1.0, tol);
    EXPECT_LT(e, 20.0 * tol) << "tol " << tol;
    EXPECT_LT(e, 0.2 * previous) << "tol " << tol;  // tighter tolerance, smaller error
    previous = e;
  }
}

TEST(Adaptive, SubstepsCoverTheStepAndCarryTheTrialStep) {
  Options o = spaceOptions(0.05);
  o.integrator = IntegratorKind::Adaptive;
  o.tolerance = 1e-8;
  auto built = springPair(o, SpringPairSpec{});  // 1 + 1 kg, 100 N/m, stretched 0.1 m
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(20));
  EXPECT_DOUBLE_EQ(sim.state().t, 1.0);
  // several substeps per output step, each far shorter than dt
  EXPECT_GT(sim.forceEvaluations(), 20 * 3 * 3);
  EXPECT_GT(sim.state().h_next, 0.0);
  EXPECT_LT(sim.state().h_next, 0.05);
}

// ---- free rigid body ----

struct TopCase {
  IntegratorKind kind;
  double h;
  double angle_tol;   // rad, precession angle after 2 s
  double energy_tol;  // relative
};

class SymmetricTop : public testing::TestWithParam<TopCase> {};

TEST_P(SymmetricTop, PrecessesAtTheAnalyticRateKeepingEnergyAndMomentum) {
  // A hoop (I1 = I2 = m r^2 / 2, I3 = m r^2 about its axle y) spun off its
  // axle: the axle sweeps a cone about the fixed L at the rate |L| / I1.
  const TopCase c = GetParam();
  Options o = spaceOptions(c.h);
  o.integrator = c.kind;
  o.tolerance = 1e-9;
  ModelBuilder b(o, farGround());
  BodySpec s = hoop(24, 1.0, 1.0);
  s.angular_velocity = Vec3(0.7, 3.0, 0.0);
  b.addBody(s);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  const double I1 = 0.5, T = 2.0;
  const Vec3 L = bodyMom(sim.state().y, 0);
  const Vec3 Lhat = L.normalized();
  const Vec3 axis0 = Vec3::UnitY();
  const double e0 = sim.energy().total();
  ASSERT_TRUE(sim.step(std::llround(T / c.h)));
  const Vec3 axis = Quat(bodyRot(sim.state().y, 0)) * Vec3::UnitY();
  EXPECT_NEAR(std::acos(axis.dot(Lhat)), std::acos(axis0.dot(Lhat)), c.angle_tol);
  const Vec3 p0 = (axis0 - axis0.dot(Lhat) * Lhat).normalized();
  const Vec3 p1 = (axis - axis.dot(Lhat) * Lhat).normalized();
  const double angle = std::atan2(Lhat.dot(p0.cross(p1)), p0.dot(p1));
  EXPECT_NEAR(std::remainder(angle - L.norm() / I1 * T, 2 * kPi), 0.0, c.angle_tol);
  // no torque: every integrator keeps L to round-off
  EXPECT_LT((bodyMom(sim.state().y, 0) - L).norm(), 1e-12);
  EXPECT_NEAR(sim.energy().total(), e0, c.energy_tol * e0);
  EXPECT_NEAR(Quat(bodyRot(sim.state().y, 0)).norm(), 1.0, 1e-12);
}

// |L| / I1 = 6.16 rad/s: omega h = 0.06 at h = 1e-2
INSTANTIATE_TEST_SUITE_P(Integrators, SymmetricTop,
                         testing::Values(TopCase{IntegratorKind::SemiImplicitEuler, 1e-3, 2e-3, 1e-6},
                                         TopCase{IntegratorKind::VelocityVerlet, 1e-3, 2e-3, 1e-6},
                                         TopCase{IntegratorKind::Rk4, 1e-2, 1e-5, 1e-7},
                                         TopCase{IntegratorKind::ImplicitEuler, 1e-3, 5e-2, 1e-2},
                                         TopCase{IntegratorKind::Adaptive, 1e-2, 1e-5, 1e-7}),
                         [](const auto& info) { return std::string(integratorName(info.param.kind)); });

// ---- bookkeeping shared by all integrators ----

class EveryIntegrator : public testing::TestWithParam<IntegratorKind> {};

TEST_P(EveryIntegrator, DriveWorkAccountsForTheEnergyGain) {
  // the car in space, all wheels driven: kinetic energy gained = drive work
  CarPlacement at;
  at.on_ground = false;
  Options o = spaceOptions(1e-4);
  o.integrator = GetParam();
  CarParams p;
  p.coupling = WheelCoupling::Bearing;  // fewer stiff springs: the implicit run stays short
  p.rim_points = 8;
  auto built = reportCar(o, farGround(), p, at);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.drive_torque = 0.5;
  const double e0 = sim.energy().total();
  ASSERT_TRUE(sim.step(2000));
  const double gained = sim.energy().total() - e0;
  EXPECT_GT(sim.state().drive_work, 0.1);
  EXPECT_NEAR(gained, sim.state().drive_work, 2e-3 * sim.state().drive_work);
}

TEST_P(EveryIntegrator, SaveAndRestoreContinuesBitForBit) {
  // the report's car on a wave with drive, brake and steering, and a
  // damping-free spring pair (where Verlet reuses its last evaluation)
  Options o;
  o.dt = GetParam() == IntegratorKind::ImplicitEuler ? 2e-4 : 5e-5;
  o.integrator = GetParam();
  o.tolerance = 1e-5;
  CarPlacement at;
  at.wheel_spin = 5.0;
  CarParams p;
  p.coupling = WheelCoupling::Bearing;
  p.rim_points = 8;
  auto car = reportCar(o, makeCosineWave(0.5, 2 * kPi), p, at);
  Options free = spaceOptions(1e-3);
  free.integrator = GetParam();
  SpringPairSpec spun;  // 1 and 2 kg on 300 N/m, stretched 0.2 m, the first moving sideways
  spun.m2 = 2.0;
  spun.stiffness = 300.0;
  spun.stretch = 0.2;
  spun.v1 = Vec3(0, 0.3, 0);
  auto pair = springPair(free, spun);
  for (const BuiltModel* built : {&car, &pair}) {
    Simulator x(built->model, built->initial);
    if (!x.controls().empty()) {
      x.controls()[0].drive_torque = 0.3;
      x.controls()[2].brake_torque = 0.01;
      x.controls()[0].steer = 0.2;
    }
    ASSERT_TRUE(x.step(300));
    const State saved = x.state();
    ASSERT_TRUE(x.step(300));
    Simulator z(built->model, built->initial);
    z.restore(saved);
    ASSERT_TRUE(z.step(300));
    EXPECT_EQ(0, std::memcmp(x.state().y.data(), z.state().y.data(), sizeof(double) * x.state().y.size()));
    EXPECT_EQ(x.state().drive_work, z.state().drive_work);
    EXPECT_EQ(x.state().h_next, z.state().h_next);
  }
}

TEST_P(EveryIntegrator, CountsForceEvaluations) {
  Options o = spaceOptions(1e-3);
  o.integrator = GetParam();
  ModelBuilder b(o, farGround());
  b.addParticle(1.0, Vec3::Zero(), Vec3(1, 0, 0), false);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(10));
  const long long n = sim.forceEvaluations();
  switch (GetParam()) {
    case IntegratorKind::SemiImplicitEuler: EXPECT_EQ(n, 10); break;
    case IntegratorKind::VelocityVerlet: EXPECT_EQ(n, 11); break;   // reuses the end forces
    case IntegratorKind::Rk4: EXPECT_EQ(n, 40); break;
    case IntegratorKind::ImplicitEuler: EXPECT_EQ(n, 10 * (6 + 1)); break;  // n + 1 per step
    case IntegratorKind::Adaptive: EXPECT_EQ(n, 10 * 4); break;     // one substep each, fresh k1
  }
}

INSTANTIATE_TEST_SUITE_P(Integrators, EveryIntegrator, testing::ValuesIn(kAll), kindName);

}  // namespace
