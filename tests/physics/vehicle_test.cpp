// The car: momentum bookkeeping of drive and brake, rolling on an incline
// against the analytic acceleration, and the report's four experiments.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "physics/checks/diagnostics.hpp"
#include "physics/checks/telemetry.hpp"
#include "support/scenes.hpp"
#include "support/fit.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

// a = g sin(theta) M / (M + sum I_w / r^2) for the report's car (ring wheels)
double rollingAcceleration(double theta) { return 9.8 * std::sin(theta) * 1.4 / 1.8; }

using support::fittedAcceleration;

}  // namespace

TEST(Drive, TorqueHasAnEqualReactionSoAngularMomentumIsConserved) {
  CarPlacement at;
  at.on_ground = false;
  auto built = reportCar(spaceOptions(1e-4), farGround(), {}, at);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.drive_torque = 2.0;
  const Vec3 L0 = angularMomentum(sim.model(), sim.state());
  ASSERT_TRUE(sim.step(20000));
  // without the reaction, L would have grown by 4 * 2 N m * 2 s = 16 N m s
  EXPECT_LT((angularMomentum(sim.model(), sim.state()) - L0).norm(), 1e-9);
  EXPECT_LT(linearMomentum(sim.model(), sim.state()).norm(), 1e-9);
  // and the wheels did spin up relative to the body
  EXPECT_GT(sampleVehicle(sim, 0, false).wheels[0].spin, 1.0);
}

TEST(Drive, BrakeStopsTheRelativeSpinAndConservesMomentum) {
  CarPlacement at;
  at.on_ground = false;
  at.wheel_spin = 5.0;
  auto built = reportCar(spaceOptions(1e-4), farGround(), {}, at);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.brake_torque = 0.2;
  const Vec3 L0 = angularMomentum(sim.model(), sim.state());
  ASSERT_TRUE(sim.step(30000));
  for (int w = 0; w < 4; ++w) EXPECT_NEAR(sampleVehicle(sim, 0, false).wheels[w].spin, 0.0, 1e-6);
  EXPECT_LT((angularMomentum(sim.model(), sim.state()) - L0).norm(), 1e-9);
}

TEST(Rolling, ContinuousWheelsRollDownAnInclineAtTheAnalyticAcceleration) {
  const double theta = 30 * kPi / 180;
  Options o;
  o.dt = 2e-4;
  o.contact.friction = 0.9;
  o.contact.damping = 20.0;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  auto built = reportCar(o, makeIncline(theta, Vec3::UnitX()), p);
  Simulator sim(built.model, built.initial);
  const double a = fittedAcceleration(sim, 0.5, 2.0);
  EXPECT_NEAR(a, rollingAcceleration(theta), 0.005 * rollingAcceleration(theta));
}

// --- the report's experiments (section 5), with its car ---

TEST(ReportExperiments, PlainGroundCarReachesTheNoSlipSpeed) {
  // S1 with circle wheels: the spinning wheels grip until they roll; the
  // angular momentum about the ground line is conserved, 4 I w0 =
  // (M r + 4 I / r) v, so v = 4 (0.1)(5) / (1.4 + 0.4) = 2 / 1.8 m/s
  Options o;
  o.dt = 2e-4;
  o.contact.friction = 0.5;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), p, at);
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(15000));  // 3 s: long rolling, slip long gone
  EXPECT_NEAR(speedOf(sim), 2.0 / 1.8, 1e-3 * 2.0 / 1.8);
  EXPECT_GT(bodyVel(sim.state().y, 0).x(), 0.0);
}

TEST(ReportExperiments, DownhillCarAcceleratesSteadily) {
  const double theta = kPi / 6;
  Options o;
  o.contact.friction = 0.9;
  auto built = reportCar(o, makeIncline(theta, Vec3::UnitX()));
  Simulator sim(built.model, built.initial);
  double prev = 0;
  for (int k = 1; k <= 8; ++k) {  // speed rises at every quarter second
    ASSERT_TRUE(sim.step(5000));
    EXPECT_GT(speedOf(sim), prev + 0.5);
    prev = speedOf(sim);
  }
  // the 20-point polygon wheels roll a few percent slower than a true wheel
  const double a = prev / sim.state().t;
  EXPECT_NEAR(a, rollingAcceleration(theta), 0.05 * rollingAcceleration(theta));
  EXPECT_GT(bodyVel(sim.state().y, 0).x(), 0);  // downhill is +x
}

TEST(ReportExperiments, UphillCarAcceleratesAtTheDriveTorqueClosedForm) {
  // four wheels driven by T up a 10 degree slope, rolling without slip:
  // a = (4 T / r - M g sin(theta)) / (M + sum I / r^2), M = 1.4 kg,
  // I = 0.1 kg m^2, r = 1 m
  const double theta = kPi / 18, T = 1.5;
  Options o;
  o.dt = 2e-4;
  o.contact.friction = 0.9;
  o.contact.damping = 10.0;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  auto built = reportCar(o, makeIncline(theta, -Vec3::UnitX()), p);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.drive_torque = T;
  const double expected = (4 * T / 1.0 - 1.4 * 9.8 * std::sin(theta)) / (1.4 + 4 * 0.1);
  EXPECT_NEAR(fittedAcceleration(sim, 0.5, 2.0), expected, 5e-3 * expected);
  EXPECT_GT(bodyVel(sim.state().y, 0).x(), 0.0);  // uphill is +x
}

TEST(ReportExperiments, CosineCarFailsToClimbTheCrestAndSettlesInTheValley) {
  Options o;
  o.contact.friction = 0.5;
  o.contact.damping = 20.0;
  CarPlacement at;
  at.position = Vec3(kPi, 0, 0);  // valley bottom of z = 0.5 cos x
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makeCosineWave(0.5, 2 * kPi), {}, at);
  Simulator sim(built.model, built.initial);
  double xmax = -1e9, xmin = 1e9, vmax = 0, late_vmax = 0;
  while (sim.state().t < 20.0) {
    ASSERT_TRUE(sim.step(1000));
    const double x = bodyPos(sim.state().y, 0).x();
    xmax = std::max(xmax, x);
    xmin = std::min(xmin, x);
    vmax = std::max(vmax, speedOf(sim));
    if (sim.state().t > 15.0) late_vmax = std::max(late_vmax, speedOf(sim));
  }
  EXPECT_GT(vmax, 0.5);                  // it did set off
  EXPECT_GT(xmax, kPi + 0.5);            // climbed towards the crest at 2 pi
  EXPECT_LT(xmax, 2 * kPi);              // but never reached it
  EXPECT_GT(xmin, 0.0);                  // nor the crest behind: it stays in the valley
  EXPECT_LT(late_vmax, 0.8 * vmax);      // rocking back and forth, losing motion
}

TEST(DeformableTyres, CarryTheCarOnAFlattenedPatchAndTransmitDriveTorque) {
  Options o;
  o.dt = 5e-5;
  o.contact.damping = 20.0;
  o.contact.friction = 0.9;
  CarParams p;
  p.deformable = true;
  p.coupling = WheelCoupling::Bearing;
  p.rim_points = 60;          // neighbours 5.5 mm above the lowest point
  p.tyre_stiffness = 150.0;   // soft enough to flatten more than that
  p.tread_stiffness = 150.0;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), p);
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(40000));  // 2 s: settled on its tyres
  // the tyres flatten: each wheel stands on more than one rim point, and
  // together they carry the car's weight
  std::array<int, 4> touching{};
  const auto& ws = sim.workspace();
  for (int c = 0; c < ws.ncontacts; ++c)
    if (ws.contacts[c].wheel >= 0) ++touching[ws.contacts[c].wheel];
  for (int w = 0; w < 4; ++w) EXPECT_GE(touching[w], 2) << "wheel " << w;
  double normal = 0;
  for (int c = 0; c < ws.ncontacts; ++c) normal += ws.contacts[c].normal;
  EXPECT_NEAR(normal, 1.4 * 9.8, 0.02 * 1.4 * 9.8);
  // torque through hub and spokes drives the car forward
  for (auto& c : sim.controls()) c.drive_torque = 0.5;
  const double x0 = bodyPos(sim.state().y, 0).x();
  ASSERT_TRUE(sim.step(40000));
  EXPECT_GT(bodyVel(sim.state().y, 0).x(), 0.5);
  EXPECT_GT(bodyPos(sim.state().y, 0).x(), x0 + 0.5);
}

TEST(DeformableTyres, SpokesAndTreadConserveMomentumInSpace) {
  CarParams p;
  p.deformable = true;
  p.coupling = WheelCoupling::Bearing;
  CarPlacement at;
  at.on_ground = false;
  at.wheel_spin = 4.0;
  auto built = reportCar(spaceOptions(5e-5), farGround(), p, at);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.drive_torque = 0.3;
  const Vec3 L0 = angularMomentum(sim.model(), sim.state());
  ASSERT_TRUE(sim.step(20000));
  EXPECT_LT((angularMomentum(sim.model(), sim.state()) - L0).norm(), 1e-9 * (1 + L0.norm()));
  EXPECT_LT(linearMomentum(sim.model(), sim.state()).norm(), 1e-10);
}

TEST(LoneWheel, HoopRollsDownAnInclineAtHalfGSinTheta) {
  // a hoop (I = m r^2) rolling without slip: a = g sin(theta) / (1 + I / m r^2)
  const double theta = 25 * kPi / 180;
  Options o;
  o.dt = 1e-4;
  o.contact.friction = 0.9;
  o.contact.damping = 60.0;  // damping ratio ~0.5 for 2 kg on 2000 N/m: the set-down bounce dies out
  ModelBuilder b(o, makeIncline(theta, Vec3::UnitX()));
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.wheel_radius = 0.4;
  p.wheel_mass = 2.0;
  addLoneWheel(b, "hoop", p, CarPlacement{});
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  const double a = fittedAcceleration(sim, 0.5, 2.0);
  EXPECT_NEAR(a, 9.8 * std::sin(theta) / 2, 1e-3 * 9.8 * std::sin(theta) / 2);
  // rolling, not sliding: the contact point does not slip
  EXPECT_LT(sampleVehicle(sim, 0, false).wheels[0].slip, 1e-6);
}
