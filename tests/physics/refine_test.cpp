// A refinement at a safe point (Simulator::refine): the run goes on at the
// same ticks with more integrator steps per tick, and moves as an
// integrator at the finer step does.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

SpringPairSpec pairSpec() {
  SpringPairSpec p;
  p.m1 = 1.0;
  p.m2 = 3.0;
  p.stiffness = 1000.0;
  p.damping = 0.0;
  p.stretch = 0.01;
  return p;
}

double separation(const Simulator& s) { return s.state().y[6] - s.state().y[0]; }

// Mean period from upward zero crossings of the stretch over `duration` more.
double measuredPeriod(Simulator& sim, double duration) {
  std::vector<double> crossings;
  const double end = sim.state().t + duration;
  double prev = separation(sim) - 1.0, tprev = sim.state().t;
  while (sim.state().t < end) {
    EXPECT_TRUE(sim.step());
    const double x = separation(sim) - 1.0, t = sim.state().t;
    if (prev < 0 && x >= 0) crossings.push_back(tprev + (t - tprev) * (-prev) / (x - prev));
    prev = x;
    tprev = t;
  }
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

}  // namespace

// Symplectic Euler at h oscillates at (2/h) asin(omega h / 2): after the
// refinement to 4 substeps of a 5 ms tick it oscillates at the 1.25 ms
// figure, not the 5 ms one, while the tick and time go on at 5 ms.
TEST(Refine, TheRunOscillatesAtTheFinerStepsDiscreteFrequency) {
  const double dt = 5e-3;
  const SpringPairSpec spec = pairSpec();
  const BuiltModel built = springPair(spaceOptions(dt), spec);
  Simulator sim(built.model, built.initial);
  const double omega = spec.omega();
  auto discrete = [&](double h) { return 2.0 / h * std::asin(omega * h / 2.0); };
  const double before = 2 * kPi / measuredPeriod(sim, 10.0);
  EXPECT_NEAR(before, discrete(dt), 2e-4 * discrete(dt));
  const long long tick = sim.state().tick;
  sim.refine(4);
  EXPECT_EQ(sim.model().opt.substeps, 4);
  EXPECT_EQ(sim.state().tick, tick);
  const double after = 2 * kPi / measuredPeriod(sim, 10.0);
  EXPECT_NEAR(after, discrete(dt / 4), 2e-4 * discrete(dt / 4));
  // the two figures really differ: by about (omega h)^2 / 24 (1 - 1/16),
  // 1.3e-3 relative, 6x the tolerance of the measurement above
  EXPECT_GT(std::abs(discrete(dt) - discrete(dt / 4)), 1e-3 * omega);
  EXPECT_DOUBLE_EQ(sim.state().t, static_cast<double>(sim.state().tick) * dt);
}

// A re-simulation refines at the same tick on a Simulator of its own: that
// equals one built on the refined model and given the state, bit for bit.
TEST(Refine, ContinuesAsASimulatorBuiltWithTheSubstepsBitForBit) {
  Options o;
  o.dt = 2e-4;
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), {}, at);
  Simulator a(built.model, built.initial);
  a.controls()[2].drive_torque = a.controls()[3].drive_torque = 0.3;
  ASSERT_TRUE(a.step(500));
  o.substeps = 2;
  auto fine = reportCar(o, makePlane(Vec3::UnitZ(), 0), {}, at);
  Simulator b(fine.model, fine.initial);
  b.restore(a.state());
  a.refine(2);
  ASSERT_TRUE(a.step(500));
  ASSERT_TRUE(b.step(500));
  EXPECT_EQ(a.state().tick, 1000);
  EXPECT_TRUE(a.state().y == b.state().y);
  EXPECT_EQ(a.specialised(), b.specialised());
  EXPECT_EQ(a.ringCar(), b.ringCar());
  EXPECT_THROW(a.refine(0), std::invalid_argument);
  EXPECT_THROW(a.refine(Simulator::kMaxSubsteps + 1), std::invalid_argument);
}
