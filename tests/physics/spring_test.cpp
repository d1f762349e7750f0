// Two point masses joined by a spring, in space.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/checks/diagnostics.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

struct Pair {
  BuiltModel built;
  double omega;  // sqrt(k / reduced mass)
};

Pair springPair(double h, double k, double c, double m1, double m2, double stretch) {
  SpringPairSpec p;
  p.m1 = m1;
  p.m2 = m2;
  p.stiffness = k;
  p.damping = c;
  p.stretch = stretch;
  return {springPair(spaceOptions(h), p), p.omega()};
}

double separation(const Simulator& s) { return s.state().y[6] - s.state().y[0]; }

// Mean period from upward zero crossings of the stretch, linearly interpolated.
double measuredPeriod(Simulator& sim, double duration) {
  std::vector<double> crossings;
  double prev = separation(sim) - 1.0, tprev = sim.state().t;
  while (sim.state().t < duration) {
    sim.step();
    const double x = separation(sim) - 1.0, t = sim.state().t;
    if (prev < 0 && x >= 0) crossings.push_back(tprev + (t - tprev) * (-prev) / (x - prev));
    prev = x;
    tprev = t;
  }
  return (crossings.back() - crossings.front()) / (crossings.size() - 1);
}

}  // namespace

TEST(Spring, FrequencyMatchesTheSymplecticEulerDispersionRelation) {
  // symplectic Euler oscillates at (2/h) asin(omega h / 2), not omega
  const double h = 5e-3;  // omega h = 0.18
  auto p = springPair(h, 1000.0, 0.0, 1.0, 3.0, 0.01);
  Simulator sim(p.built.model, p.built.initial);
  const double T = measuredPeriod(sim, 20.0);
  const double discrete = 2.0 / h * std::asin(p.omega * h / 2.0);
  EXPECT_NEAR(2 * kPi / T, discrete, 2e-4 * discrete);
  EXPECT_GT(std::abs(discrete - p.omega), 1e-3 * p.omega);  // the two really differ here
}

// Mean of the energy over the next n steps (sampled after each).
double meanEnergy(Simulator& sim, long n) {
  double sum = 0.0;
  for (long i = 0; i < n; ++i) {
    sim.step();
    sum += sim.energy().total();
  }
  return sum / static_cast<double>(n);
}

TEST(Spring, UndampedEnergyStaysBounded) {
  auto p = springPair(1e-3, 5000.0, 0.0, 0.5, 0.5, 0.05);
  Simulator sim(p.built.model, p.built.initial);
  const double e0 = sim.energy().total();
  double lo = e0, hi = e0;
  for (int i = 0; i < 20000; ++i) {
    sim.step();
    const double e = sim.energy().total();
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  // symplectic: the energy error oscillates at O(omega h), it does not grow
  const double wh = p.omega * 1e-3;
  EXPECT_LT((hi - lo) / e0, 1.5 * wh);
  EXPECT_GT((hi - lo) / e0, 0.3 * wh);  // the oscillation is really there
}

TEST(Spring, UndampedEnergyDoesNotDrift) {
  // the oscillation (14% here) averages out over whole periods: the mean
  // over ten periods at the start and after 20 s agree far more closely
  const double h = 1e-3;
  auto p = springPair(h, 5000.0, 0.0, 0.5, 0.5, 0.05);
  Simulator sim(p.built.model, p.built.initial);
  const double period = kPi / std::asin(p.omega * h / 2.0) * h;  // of the discrete oscillation
  const long n = std::lround(10 * period / h);
  const double first = meanEnergy(sim, n);
  sim.step(20000);
  const double later = meanEnergy(sim, n);
  EXPECT_NEAR(later, first, 1e-3 * first);
}

TEST(Spring, DashpotDissipatesAtTheDampedRate) {
  // over one damped period x and v both shrink by exp(-zeta omega T_d), so
  // the energy averaged over a whole period falls by exp(-2 zeta omega t)
  // between windows t apart; zeta = c / (2 sqrt(k mu))
  const double k = 1000.0, c = 2.0, m = 1.0, h = 1e-4;  // mu = 0.5
  auto p = springPair(h, k, c, m, m, 0.01);
  Simulator sim(p.built.model, p.built.initial);
  const double zeta = c / (2.0 * std::sqrt(k * 0.5));
  const double Td = 2 * kPi / (p.omega * std::sqrt(1 - zeta * zeta));
  const long n = std::lround(Td / h);
  const double first = meanEnergy(sim, n);
  const long gap = 7 * n;  // windows 8 periods apart (1.1 s)
  sim.step(gap - n);
  const double later = meanEnergy(sim, n);
  const double expected = first * std::exp(-2.0 * zeta * p.omega * (gap * h));
  EXPECT_NEAR(later, expected, 0.01 * expected);
}

TEST(Spring, InternalForcesConserveMomentum) {
  auto p = springPair(1e-3, 800.0, 3.0, 1.0, 2.0, 0.2);
  State s0 = p.built.initial;
  s0.y.segment<3>(3) = Vec3(0.3, -1.0, 0.5);  // give them different velocities
  s0.y.segment<3>(9) = Vec3(-0.2, 0.4, 1.0);
  Simulator sim(p.built.model, s0);
  const Vec3 P0 = linearMomentum(sim.model(), sim.state());
  const Vec3 L0 = angularMomentum(sim.model(), sim.state());
  sim.step(3000);
  EXPECT_LT((linearMomentum(sim.model(), sim.state()) - P0).norm(), 1e-12);
  // symplectic Euler conserves angular momentum exactly for central forces:
  // x_{n+1} x v_{n+1} = x_n x v_{n+1}, and sum x_i x F_i = 0
  EXPECT_GT(L0.norm(), 0.1);
  EXPECT_LT((angularMomentum(sim.model(), sim.state()) - L0).norm(), 1e-12 * L0.norm());
}
