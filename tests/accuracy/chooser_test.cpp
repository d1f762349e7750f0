// chooseSettings against the contract of docs/accuracy.md: the setting it
// picks, run over the whole scene, is within the tolerance of the converged
// solution of the scene as written; it never picks a step beyond the scene's
// stability limit; it names what it refused.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/integrators/integrator.hpp"
#include "scenes.hpp"

namespace groundsim::accuracy {
namespace {

double realised(const Choice& c, const Trajectory& ref) {
  const Trajectory run = runTrajectory(c.scenario, c.scenario.duration);
  EXPECT_TRUE(run.healthy) << run.failure;
  return compareRuns(run, ref).value();
}

// The report's car (20 rim points) rolling down 30 degrees from rest.
TEST(Chooser, MeetsTheToleranceOnTheReportsDownhill) {
  const scenario::Scenario s = test::config("downhill.json");
  const Trajectory ref = test::reference(s, 5e-6);
  for (double tol : {0.1, 0.01}) {
    const Choice c = chooseSettings(s, tol);
    SCOPED_TRACE(c.line());
    EXPECT_TRUE(c.meets);
    EXPECT_LE(realised(c, ref), tol);
  }
}

// The sedan's slalom: steering reversals at 20 m/s.
TEST(Chooser, MeetsTheToleranceOnTheSedansSlalom) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=6"});
  const Trajectory ref = test::reference(s, 0.02 / 64);
  for (double tol : {0.1, 0.01, 0.001}) {
    const Choice c = chooseSettings(s, tol);
    SCOPED_TRACE(c.line());
    EXPECT_LE(realised(c, ref), tol);
  }
}

// Contact between bodies: a lone wheel climbing a kerb. The reference
// refines contact with the step (collisions.min_substeps).
TEST(Chooser, MeetsTheToleranceAcrossAnImpact) {
  const scenario::Scenario s = test::config("accuracy/lone_wheel.json");
  const Trajectory ref = test::reference(s, 0.02 / 128, 64);
  const Choice c = chooseSettings(s, 0.1);
  SCOPED_TRACE(c.line());
  EXPECT_LE(realised(c, ref), 0.1);
}

// A ground 100 times stiffer than the report's: the largest stable step
// shrinks by 10; the chooser stays inside it and says why.
TEST(Chooser, StaysInsideTheStabilityLimitAndNamesIt) {
  const scenario::Scenario s = test::config("plain.json", {"contact.stiffness=200000", "duration=1",
                                                           "vehicle.wheel_model=\"circle\"",
                                                           "vehicle.coupling=\"bearing\""});
  const Choice c = chooseSettings(s, 0.1);
  SCOPED_TRACE(c.report());
  const IntegratorTrial* chosen = nullptr;
  for (const IntegratorTrial& t : c.trials)
    if (t.usable && t.kind == c.integrator && t.contact_substeps == c.contact_substeps) chosen = &t;
  ASSERT_NE(chosen, nullptr);
  ASSERT_TRUE(std::isfinite(chosen->stability_dt));
  EXPECT_LT(c.dt, chosen->stability_dt);
  EXPECT_NE(chosen->refusal.find("stiffest mode"), std::string::npos);
  EXPECT_TRUE(runTrajectory(c.scenario, s.duration).healthy);
}

// The sedan keeps the ground's default stick-slip friction, which RK4 does
// not integrate: its trial is refused, naming the field.
TEST(Chooser, NamesTheIntegratorsTheSceneRefuses) {
  const scenario::Scenario s = test::config("sedan.json", {"duration=1"});
  const Choice c = chooseSettings(s, 0.1);
  bool named = false;
  for (const IntegratorTrial& t : c.trials)
    if (t.kind == IntegratorKind::Rk4) {
      EXPECT_FALSE(t.usable);
      named = t.refusal.find("/contact/friction_model") != std::string::npos;
    }
  EXPECT_TRUE(named) << c.report();
  EXPECT_NE(c.integrator, IntegratorKind::Rk4);
}

// The chosen scenario's document says what runs: another process given it
// runs the same settings.
TEST(Chooser, TheChosenDocumentRoundTrips) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=2"});
  const Choice c = chooseSettings(s, 0.01);
  const scenario::Scenario again = scenario::parseScenario(c.scenario.document);
  EXPECT_EQ(again.options.integrator, c.integrator);
  EXPECT_EQ(again.options.dt, c.dt);
  EXPECT_EQ(again.options.collision.min_substeps, c.contact_substeps);
}

}  // namespace
}  // namespace groundsim::accuracy
