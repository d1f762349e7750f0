// The pilot's cost against the contract of docs/accuracy.md, "The pilot's
// cost": a long run's pilot takes at most its share of the run's predicted
// work (counted in work units, not timed), a short scene is piloted whole,
// and an integrator left out because it cannot be cheaper really could not
// have been.
#include <gtest/gtest.h>

#include <string>

#include "scenes.hpp"

namespace groundsim::accuracy {
namespace {

bool notPiloted(const IntegratorTrial& t) { return !t.usable && t.refusal.rfind("not piloted:", 0) == 0; }

// A 60 s run: the scout chooses, the pilot stays within 20% of the run it
// prepares, and the choice still meets the tolerance over the whole run.
TEST(PilotBudget, ALongRunsPilotTakesAtMostItsShareAndTheChoiceMeets) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=60"});
  const Trajectory ref = test::reference(s, 0.02 / 64);
  PilotOptions o;
  o.max_share = 0.2;
  for (double tol : {0.1, 0.01}) {
    const Choice c = chooseSettings(s, tol, o);
    SCOPED_TRACE(c.report());
    EXPECT_LT(c.pilot_duration, s.duration);
    EXPECT_FALSE(c.pilot_bound.empty());
    EXPECT_GT(c.pilot_work, 0.0);
    EXPECT_LE(c.pilot_work, o.max_share * c.run_work);
    const Trajectory run = runTrajectory(c.scenario, s.duration);
    ASSERT_TRUE(run.healthy) << run.failure;
    EXPECT_LE(compareRuns(run, ref).value(), tol);
  }
}

// Unbounded (max_share 0, the default) the same scene's pilot runs it
// whole and takes more than the bounded one: the bound is what made it cheap.
TEST(PilotBudget, UnboundedThePilotRunsTheWholeScene) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=60"});
  const Choice c = chooseSettings(s, 0.01);
  EXPECT_EQ(c.pilot_duration, 60.0);
  EXPECT_TRUE(c.pilot_bound.empty());
  EXPECT_EQ(c.line().find("piloted on the first"), std::string::npos) << c.line();
  PilotOptions bounded;
  bounded.max_share = 0.2;
  const Choice b = chooseSettings(s, 0.01, bounded);
  EXPECT_GT(c.pilot_work, b.pilot_work);
  // a choice from part of the scene says so where it is read
  EXPECT_NE(b.line().find("piloted on the first"), std::string::npos) << b.line();
}

// A pilot within min_pilot_work (0 by default) is not cut, however cheap
// the run: the sedan's whole 60 s pilot takes less than 5e7 units, so
// after the scout it runs whole.
TEST(PilotBudget, APilotWithinTheFloorRunsWhole) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=60"});
  PilotOptions o;
  o.max_share = 0.2;
  o.min_pilot_work = 5e7;
  const Choice c = chooseSettings(s, 0.01, o);
  SCOPED_TRACE(c.report());
  EXPECT_EQ(c.pilot_duration, 60.0);
  EXPECT_NE(c.pilot_bound.find("the whole scene"), std::string::npos);
  EXPECT_LE(c.pilot_work, o.min_pilot_work);
}

// A scene no longer than two scouts is piloted whole, with no scout.
TEST(PilotBudget, AShortSceneIsPilotedWhole) {
  PilotOptions o;
  o.max_share = 0.2;
  const Choice one = chooseSettings(test::config("sedan_slalom.json", {"duration=1"}), 0.01, o);
  EXPECT_EQ(one.pilot_duration, 1.0);
  EXPECT_TRUE(one.pilot_bound.empty());
  const Choice two = chooseSettings(test::config("sedan_slalom.json", {"duration=20"}), 0.01, o);
  EXPECT_FALSE(two.pilot_bound.empty());
}

// Branch and bound: on the report's rim car (semi-implicit Euler meets 10%
// at its coarsest stable step) velocity Verlet, two evaluations a step at
// the same step, cannot be cheaper and is not piloted. Piloted alone it
// indeed costs no less than the choice made without it.
TEST(PilotBudget, AnIntegratorLeftOutCouldNotHaveBeenCheaper) {
  const scenario::Scenario s = test::config("cosine.json", {"duration=2"});
  PilotOptions o;
  o.other_models = false;
  const Choice c = chooseSettings(s, 0.1, o);
  SCOPED_TRACE(c.report());
  int left_out = 0;
  for (const IntegratorTrial& t : c.trials) {
    if (!notPiloted(t)) continue;
    ++left_out;
    PilotOptions alone = o;
    alone.integrators = {t.kind};
    const Choice only = chooseSettings(s, 0.1, alone);
    SCOPED_TRACE(only.line());
    EXPECT_TRUE(only.meets);
    EXPECT_GE(only.predicted_work, c.predicted_work);
  }
  EXPECT_GE(left_out, 1);
}

}  // namespace
}  // namespace groundsim::accuracy
