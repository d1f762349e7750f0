// step() never allocates, with every integrator, from the first step on.
// Counted at malloc (Eigen allocates with malloc, operator new calls it), by
// interposing malloc, calloc, realloc and the aligned allocators in this
// test binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <string>

#include "support/scenes.hpp"
#include "support/malloc_counter.hpp"

using groundsim::test::g_allocations;

using namespace groundsim;
using namespace groundsim::test;

namespace {

TEST(Allocation, TheCounterSeesEigenAndNew) {
  // the counter must be able to fail: an Eigen vector and a new both count
  const long before = g_allocations.load();
  Eigen::VectorXd v(1000);
  v.setZero();
  auto* p = new std::string(100, 'x');
  EXPECT_GE(g_allocations.load() - before, 2);
  delete p;
}

class StepAllocation : public testing::TestWithParam<IntegratorKind> {};

TEST_P(StepAllocation, FromTheFirstStepNothingIsAllocated) {
  Options o;
  o.dt = 5e-5;
  o.integrator = GetParam();
  // the ODE integrators take the smooth friction (stick-slip is theirs to refuse)
  if (GetParam() != IntegratorKind::SemiImplicitEuler && GetParam() != IntegratorKind::VelocityVerlet)
    o.contact.friction_model = FrictionModel::Regularized;
  CarPlacement at;
  at.wheel_spin = 5.0;
  CarParams p;
  p.rim_points = 8;
  auto built = reportCar(o, makeCosineWave(0.5, 2 * kPi), p, at);
  Simulator sim(built.model, built.initial);
  sim.controls()[1].brake_torque = 0.05;
  sim.controls()[0].steer = 0.2;
  const long before = g_allocations.load();
  ASSERT_TRUE(sim.step(600));  // includes energy checks every 256 steps
  (void)sim.energy();          // and a sampled energy
  EXPECT_EQ(g_allocations.load(), before);
}

INSTANTIATE_TEST_SUITE_P(Integrators, StepAllocation,
                         testing::Values(IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet,
                                         IntegratorKind::Rk4, IntegratorKind::ImplicitEuler,
                                         IntegratorKind::Adaptive),
                         [](const auto& info) { return std::string(integratorName(info.param)); });

TEST(Allocation, VerletWithItsForceCacheAllocatesNothing) {
  // an undamped frictionless scene: Verlet reuses its end-of-step forces
  Options o = spaceOptions(1e-3);
  o.integrator = IntegratorKind::VelocityVerlet;
  SpringPairSpec pair;
  pair.stretch = 0.2;
  auto built = springPair(o, pair);
  Simulator sim(built.model, built.initial);
  const long before = g_allocations.load();
  ASSERT_TRUE(sim.step(600));
  EXPECT_EQ(g_allocations.load(), before);
}

}  // namespace
