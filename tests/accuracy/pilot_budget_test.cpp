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
// (The sedan's pilot is cheap: without min_pilot_work 0 the floor would
// let it run whole, below.)
TEST(PilotBudget, ALongRunsPilotTakesAtMostItsShareAndTheChoiceMeets) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=60"});
  const Trajectory ref = test::reference(s, 0.02 / 64);
  PilotOptions o;
  o.min_pilot_work = 0.0;
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

// Unbounded (max_share 0) the same scene's pilot runs it whole and takes
// more than the bounded one: the bound is what made it cheap.
TEST(PilotBudget, UnboundedThePilotRunsTheWholeScene) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=60"});
  PilotOptions whole;
  whole.max_share = 0.0;
  const Choice c = chooseSettings(s, 0.01, whole);
  EXPECT_EQ(c.pilot_duration, 60.0);
  EXPECT_TRUE(c.pilot_bound.empty());
  PilotOptions bounded;
  bounded.min_pilot_work = 0.0;
  EXPECT_GT(c.pilot_work, chooseSettings(s, 0.01, bounded).pilot_work);
}

// A pilot within min_pilot_work is not cut, however cheap the run: the
// sedan's whole 60 s pilot takes less, so after the scout it runs whole.
TEST(PilotBudget, APilotWithinTheFloorRunsWhole) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=60"});
  const PilotOptions o;
  const Choice c = chooseSettings(s, 0.01, o);
  SCOPED_TRACE(c.report());
  EXPECT_EQ(c.pilot_duration, 60.0);
  EXPECT_NE(c.pilot_bound.find("the whole scene"), std::string::npos);
  EXPECT_LE(c.pilot_work, o.min_pilot_work);
}

// A scene up to bounded_after (20 s) is piloted whole, with no scout; so is
// one no longer than two scouts, whatever bounded_after says.
TEST(PilotBudget, AShortSceneIsPilotedWhole) {
  const scenario::Scenario s = test::config("sedan_slalom.json", {"duration=20"});
  const Choice c = chooseSettings(s, 0.01);
  EXPECT_EQ(c.pilot_duration, 20.0);
  EXPECT_TRUE(c.pilot_bound.empty());
  PilotOptions all;
  all.bounded_after = 0.0;
  all.min_pilot_work = 0.0;
  EXPECT_LT(chooseSettings(s, 0.01, all).pilot_duration, 20.0);
  const Choice one = chooseSettings(test::config("sedan_slalom.json", {"duration=1"}), 0.01, all);
  EXPECT_EQ(one.pilot_duration, 1.0);
  EXPECT_TRUE(one.pilot_bound.empty());
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
