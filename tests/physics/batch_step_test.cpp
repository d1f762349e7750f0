// The specialised rigid-car step (fast_car.hpp) and the batched step
// (batch_step.hpp): a car stepped in a batch is the same car stepped alone,
// and the specialised step is the general force loop up to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "physics/kernels/batch_step.hpp"
#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

// The fast preset's car: circle wheels on bearings, dt 2.5 ms.
BuiltModel fastCar(GroundPtr ground, bool deterministic = false, double spin = 5.0) {
  Options o;
  o.dt = 2.5e-3;
  o.deterministic = deterministic;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  p.bearing_stiffness = 5e3;
  p.bearing_damping = 10.0;
  CarPlacement at;
  at.wheel_spin = spin;
  return reportCar(o, std::move(ground), p, at);
}

// Car i's commands at step k: drive, brake and steering that differ per car
// and change over the run, so lanes take different branches (sliding,
// sticking, braking, a wheel lifting).
void command(std::vector<WheelControl>& c, int car, long long k) {
  for (size_t w = 0; w < c.size(); ++w) {
    c[w].drive_torque = (w >= 2 ? 0.3 : 0.0) * std::sin(0.01 * static_cast<double>(k) + car);
    c[w].brake_torque = (car % 3 == 1 && k > 200) ? 2.0 : 0.0;
    c[w].steer = car % 2 == 0 ? 0.3 * std::sin(0.005 * static_cast<double>(k)) : 0.0;
  }
}

double maxDiff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).lpNorm<Eigen::Infinity>(); }

void expectBatchMatchesAlone(bool deterministic) {
  const BuiltModel built = fastCar(makeIncline(0.1, Vec3::UnitX()), deterministic);
  ASSERT_EQ(BatchStep::unsupported(*built.model), nullptr);
  constexpr int kCars = 6;  // one full group of four and one half-empty
  constexpr long long kSteps = 600, kChunk = 50;
  std::vector<Simulator> alone;
  std::vector<State> batch(kCars, built.initial);
  for (int i = 0; i < kCars; ++i) alone.emplace_back(built.model, built.initial);
  BatchStep step(built.model);
  bool identical = true;
  for (long long k = 0; k < kSteps; k += kChunk) {
    for (int i = 0; i < kCars; ++i) {
      batch[i].controls.resize(built.model->wheels.size());
      command(batch[i].controls, i, k);
      command(alone[i].controls(), i, k);
      ASSERT_TRUE(alone[i].step(kChunk));
    }
    step.step(batch, kChunk);
    for (int i = 0; i < kCars; ++i) {
      ASSERT_EQ(batch[i].health, Health::Ok) << batch[i].health_reason;
      EXPECT_EQ(batch[i].tick, alone[i].state().tick);
      EXPECT_EQ(batch[i].t, alone[i].state().t);
      EXPECT_LT(maxDiff(batch[i].y, alone[i].state().y), 1e-12) << "car " << i << " step " << k;
      EXPECT_NEAR(batch[i].drive_work, alone[i].state().drive_work, 1e-12);
      identical = identical && (batch[i].y.array() == alone[i].state().y.array()).all();
    }
  }
  // the same kernel in the same operation order: in the generic build not
  // a bit differs; the AVX2 build fuses multiplies and adds (FMA) in the
  // scalar and the four-lane code at different places, so there the two
  // agree to round-off only (the bound above)
  if (deterministic) EXPECT_TRUE(identical);
  // and the cars did move apart: the lanes really carried different cars
  EXPECT_GT(maxDiff(batch[0].y, batch[1].y), 1e-3);
}

TEST(BatchStep, ACarInABatchIsTheSameCarSteppedAlone) { expectBatchMatchesAlone(false); }
TEST(BatchStep, AlsoInTheDeterministicBuild) { expectBatchMatchesAlone(true); }

TEST(FastCar, TheSpecialisedStepIsTheGeneralForceLoopUpToRoundOff) {
  // downhill with brakes on the rear wheels half of the time: sticking,
  // sliding and braking contacts, as the general path computes them
  const BuiltModel built = fastCar(makeIncline(0.3, Vec3::UnitX()));
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.specialised());
  const Model& m = *built.model;
  State general = built.initial;
  general.controls.resize(m.wheels.size());
  general.applied.resize(m.wheels.size());
  Workspace ws(m);
  SemiImplicitEuler sie;
  double worst = 0.0;
  for (long long k = 0; k < 2000; ++k) {
    for (size_t w = 0; w < m.wheels.size(); ++w) {
      WheelControl c;
      c.drive_torque = w < 2 ? 0.2 : 0.0;
      c.brake_torque = (k / 200) % 2 == 1 && w >= 2 ? 1.5 : 0.0;
      c.steer = 0.2 * std::sin(0.003 * static_cast<double>(k));
      sim.controls()[w] = c;
      general.controls[w] = c;
    }
    ASSERT_TRUE(sim.step());
    applyControls(m, m.opt.dt, general);
    sie.advance(m, general, ws, m.opt.dt);
    const Workspace& fast = sim.workspace();
    ASSERT_EQ(fast.ncontacts, ws.ncontacts) << "step " << k;
    for (int c = 0; c < ws.ncontacts; ++c) {
      EXPECT_EQ(fast.contacts[c].wheel, ws.contacts[c].wheel);
      EXPECT_NEAR(fast.contacts[c].normal, ws.contacts[c].normal, 1e-9 * (1.0 + ws.contacts[c].normal));
      EXPECT_LT((fast.contacts[c].friction - ws.contacts[c].friction).norm(), 1e-9);
    }
    for (size_t w = 0; w < m.wheels.size(); ++w)
      EXPECT_NEAR(fast.wheel_normal[w], ws.wheel_normal[w], 1e-9 * (1.0 + ws.wheel_normal[w]));
    worst = std::max(worst, maxDiff(sim.state().y, general.y));
  }
  // round-off grows along a chaotic-free but contact-rich run: bound it far
  // below any physical scale (metres, m/s, kg m^2/s here are all O(1))
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(bodyVel(general.y, 0).x(), 0.1);  // it did roll downhill
}

TEST(BatchStep, ADivergedCarStopsAtItsLastFiniteStateAndTheOthersGoOn) {
  const BuiltModel built = fastCar(makePlane(Vec3::UnitZ(), 0.0));
  std::vector<State> cars(5, built.initial);
  bodyVel(cars[2].y, 0).x() = 2000.0;  // beyond the 1000 m/s limit after one step
  const Eigen::VectorXd start = cars[2].y;
  BatchStep step(built.model);
  step.step(cars, 100);
  EXPECT_EQ(cars[2].health, Health::Speed);
  EXPECT_NE(cars[2].health_reason.find("speed"), std::string::npos);
  EXPECT_EQ(cars[2].tick, 0);
  EXPECT_TRUE((cars[2].y.array() == start.array()).all());
  step.step(cars, 10);  // later calls leave it alone
  EXPECT_EQ(cars[2].tick, 0);
  Simulator alone(built.model, built.initial);
  ASSERT_TRUE(alone.step(110));
  for (int i : {0, 1, 3, 4}) {
    EXPECT_EQ(cars[i].health, Health::Ok);
    EXPECT_EQ(cars[i].tick, 110);
    EXPECT_LT(maxDiff(cars[i].y, alone.state().y), 1e-12);
  }
}

TEST(BatchStep, ModelsItCannotBatchAreRefusedWithTheReason) {
  Options o;
  o.dt = 5e-5;
  const BuiltModel ring = reportCar(o, makePlane(Vec3::UnitZ(), 0.0));  // rim points, rim springs
  ASSERT_NE(BatchStep::unsupported(*ring.model), nullptr);
  try {
    BatchStep step(ring.model);
    FAIL() << "a ring car was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be batched"), std::string::npos) << e.what();
  }
  const BuiltModel wavy = fastCar(makeCosineWave(0.1, 5.0));
  EXPECT_NE(std::string(BatchStep::unsupported(*wavy.model)).find("plane"), std::string::npos);
  EXPECT_FALSE(Simulator(wavy.model, wavy.initial).specialised());
}

TEST(BatchStep, AStateOfAnotherModelIsRefused) {
  const BuiltModel built = fastCar(makePlane(Vec3::UnitZ(), 0.0));
  std::vector<State> cars(2, built.initial);
  cars[1].y.resize(3);
  BatchStep step(built.model);
  EXPECT_THROW(step.step(cars, 1), std::invalid_argument);
}

}  // namespace
