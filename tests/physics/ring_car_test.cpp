// The ring car's specialised step (ring_car.hpp): which models take it, and
// that it is the general force loop up to round-off.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"
#include "physics/kernels/ring_car.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

// The report's car (20 rim points per wheel, rim springs), dt 5e-5.
BuiltModel ringCar(GroundPtr ground, bool deterministic = false) {
  Options o;
  o.dt = 5e-5;
  o.deterministic = deterministic;
  CarPlacement at;
  at.wheel_spin = 5.0;
  return reportCar(o, std::move(ground), {}, at);
}

double maxDiff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).lpNorm<Eigen::Infinity>(); }

TEST(RingCar, TheReportsCarOnAPlaneTakesTheRingStep) {
  const BuiltModel built = ringCar(makePlane(Vec3::UnitZ(), 0.0));
  EXPECT_EQ(ringCarUnsupported(*built.model), nullptr);
  Simulator sim(built.model, built.initial);
  EXPECT_TRUE(sim.ringCar());
  EXPECT_FALSE(sim.specialised());
}

TEST(RingCar, TheDeterministicSettingAndOtherGroundsKeepTheGeneralLoop) {
  const BuiltModel det = ringCar(makePlane(Vec3::UnitZ(), 0.0), true);
  EXPECT_STREQ(ringCarUnsupported(*det.model), "physics.deterministic keeps the general loop's bits");
  EXPECT_FALSE(Simulator(det.model, det.initial).ringCar());
  const BuiltModel wavy = ringCar(makeCosineWave(0.05, 2.0));
  EXPECT_STREQ(ringCarUnsupported(*wavy.model), "the ground is not a plane");
  EXPECT_FALSE(Simulator(wavy.model, wavy.initial).ringCar());
}

TEST(RingCar, TheSpecialisedStepIsTheGeneralForceLoopUpToRoundOff) {
  // downhill, front wheels driven, the rear braked half of the time and the
  // front steered: sticking, sliding and braking rim contacts
  const BuiltModel built = ringCar(makeIncline(0.3, Vec3::UnitX()));
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.ringCar());
  const Model& m = *built.model;
  State general = built.initial;
  general.controls.resize(m.wheels.size());
  general.applied.resize(m.wheels.size());
  Workspace ws(m);
  SemiImplicitEuler sie;
  double worst = 0.0;
  int most_contacts = 0;
  bool braked_slip = false;
  for (long long k = 0; k < 6000; ++k) {
    for (size_t w = 0; w < m.wheels.size(); ++w) {
      WheelControl c;
      c.drive_torque = w < 2 ? 0.2 : 0.0;
      c.brake_torque = (k / 1000) % 2 == 1 && w >= 2 ? 1.5 : 0.0;
      c.steer = 0.2 * std::sin(0.0005 * static_cast<double>(k));
      sim.controls()[w] = c;
      general.controls[w] = c;
    }
    ASSERT_TRUE(sim.step()) << sim.state().health_reason;
    applyControls(m, m.opt.dt, general);
    sie.advance(m, general, ws, m.opt.dt);
    worst = std::max(worst, maxDiff(sim.state().y, general.y));
    most_contacts = std::max(most_contacts, ws.ncontacts);
    for (int c = 0; c < ws.ncontacts; ++c)
      braked_slip = braked_slip || (general.applied[2].brake_torque > 0 && ws.contacts[c].wheel >= 2 &&
                                    ws.contacts[c].friction.norm() > 0.999 * ws.contacts[c].mu * ws.contacts[c].normal &&
                                    ws.contacts[c].normal > 0.0);
  }
  // sums in another order round differently; along this run the states stay
  // within round-off of each other (metres, m/s, kg m^2/s: all O(1) here)
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(sim.state().drive_work, general.drive_work, 1e-9 * (1.0 + std::abs(general.drive_work)));
  EXPECT_GE(most_contacts, 4);                 // every wheel on the ground
  EXPECT_TRUE(braked_slip);                    // and a braked contact at its friction limit
  EXPECT_GT(bodyVel(general.y, 0).x(), 0.05);  // it did roll downhill
  // the workspace read after a ring step is the general loop's at that configuration
  const Workspace& rw = sim.workspace();
  ASSERT_EQ(rw.ncontacts, ws.ncontacts);
  for (int c = 0; c < ws.ncontacts; ++c) EXPECT_NEAR(rw.contacts[c].normal, ws.contacts[c].normal, 1e-6);
}

}  // namespace
