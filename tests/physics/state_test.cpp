// The state is complete: restoring a copy continues bit for bit; divergence
// is detected, reported and never leaves NaN in the state.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

TEST(State, SaveAndRestoreContinuesBitForBit) {
  Options o;
  o.dt = 1e-4;
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makeCosineWave(0.5, 2 * kPi), {}, at);
  Simulator a(built.model, built.initial);
  a.controls()[0].drive_torque = 0.3;
  a.controls()[2].brake_torque = 0.01;
  ASSERT_TRUE(a.step(3000));
  const State saved = a.state();
  ASSERT_TRUE(a.step(3000));

  Simulator b(built.model, built.initial);
  b.restore(saved);
  ASSERT_TRUE(b.step(3000));
  ASSERT_EQ(a.state().y.size(), b.state().y.size());
  EXPECT_EQ(0, std::memcmp(a.state().y.data(), b.state().y.data(), sizeof(double) * a.state().y.size()));
  EXPECT_EQ(a.state().tick, b.state().tick);
  EXPECT_EQ(a.state().t, b.state().t);
}

TEST(State, DivergenceIsReportedAndTheStateStaysFinite) {
  // ground 1e8 N/m under a 0.1 kg wheel at dt 1e-2: omega h ~ 300 >> 2
  Options o;
  o.dt = 1e-2;
  o.contact.stiffness = 1e8;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0));
  Simulator sim(built.model, built.initial);
  EXPECT_FALSE(sim.step(1000));
  EXPECT_NE(sim.state().health, Health::Ok);
  EXPECT_FALSE(sim.state().health_reason.empty());
  EXPECT_TRUE(sim.state().y.allFinite());
  const long long tick = sim.state().tick;
  EXPECT_FALSE(sim.step());  // terminal: nothing moves any more
  EXPECT_EQ(sim.state().tick, tick);
}

TEST(State, StableSettingsStayHealthy) {
  Options o;
  o.dt = 1e-4;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0));
  Simulator sim(built.model, built.initial);
  EXPECT_TRUE(sim.step(20000));
  EXPECT_EQ(sim.state().health, Health::Ok);
}
