// What a simulation owns: diagnostics leave the step's buffers alone, and a
// diverged step is undone whole.
#include <gtest/gtest.h>

#include "physics/forces/forces.hpp"
#include "physics/checks/telemetry.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

struct Snapshot {
  int ncontacts;
  std::vector<double> normal;
  std::vector<Vec3> force, torque;
  double max_depth;
};

Snapshot snap(const Workspace& ws) {
  Snapshot s{ws.ncontacts, {}, ws.body_force, ws.body_torque, ws.max_depth};
  for (int i = 0; i < ws.ncontacts; ++i) s.normal.push_back(ws.contacts[i].normal);
  return s;
}

void expectSame(const Snapshot& a, const Snapshot& b) {
  ASSERT_EQ(a.ncontacts, b.ncontacts);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.torque, b.torque);
  EXPECT_EQ(a.max_depth, b.max_depth);
}

BuiltModel restingCar() {
  Options o;
  o.dt = 2e-4;
  return reportCar(o, makeCosineWave(0.5, 2 * kPi));
}

TEST(Diagnostics, SamplingEnergyLeavesTheLastForceEvaluationAlone) {
  auto built = restingCar();
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(1000));  // landed
  const Snapshot before = snap(sim.workspace());
  ASSERT_GT(before.ncontacts, 0);
  ASSERT_GT(before.normal[0], 0.0);
  const Simulator& view = sim;
  const double e = view.energy().total();  // const: a sample cannot change the run
  (void)sampleVehicle(view, 0, true);
  expectSame(snap(sim.workspace()), before);
  EXPECT_TRUE(std::isfinite(e));
}

TEST(Diagnostics, TheEnergyCheckLeavesTheStepsForcesAlone) {
  // step 256 runs the energy check: what the workspace holds afterwards is
  // still the force evaluation of that step, as in a fresh evaluation
  auto built = restingCar();
  Simulator sim(built.model, built.initial);
  ASSERT_TRUE(sim.step(4 * Simulator::kEnergyCheckInterval - 1));  // landed
  State before = sim.state();
  ASSERT_TRUE(sim.step());  // tick 256: energy checked
  Workspace fresh(*built.model);
  applyControls(*built.model, built.model->opt.dt, before);
  computeForces(*built.model, before.y, before.applied, built.model->opt.dt, fresh);
  ASSERT_GT(fresh.ncontacts, 0);
  expectSame(snap(sim.workspace()), snap(fresh));
}

TEST(Divergence, RollbackRestoresTheWholeState) {
  // adaptive (carries h_next), driven (drive work), steering (applied moves
  // at the steer rate): a speed limit trips after a while
  Options o;
  o.dt = 1e-3;
  o.integrator = IntegratorKind::Adaptive;
  o.contact.friction_model = FrictionModel::Regularized;
  o.limits.max_speed = 0.2;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), p);
  Simulator sim(built.model, built.initial);
  for (auto& c : sim.controls()) c.drive_torque = 1.0;
  sim.controls()[0].steer = 0.5;
  State last = sim.state();
  bool ok = true;
  for (int i = 0; i < 20000 && ok; ++i) {
    last = sim.state();
    ok = sim.step();
  }
  ASSERT_FALSE(ok);
  ASSERT_GT(last.drive_work, 0.0);
  ASSERT_GT(last.applied[0].steer, 0.0);
  const State& s = sim.state();
  EXPECT_EQ(s.health, Health::Speed);
  EXPECT_TRUE((s.y.array() == last.y.array()).all());
  EXPECT_EQ(s.t, last.t);
  EXPECT_EQ(s.tick, last.tick);
  EXPECT_EQ(s.h_next, last.h_next);
  EXPECT_EQ(s.drive_work, last.drive_work);
  EXPECT_EQ(s.applied[0].steer, last.applied[0].steer);
}

}  // namespace
