// The live estimate: what it costs and how close it comes to the error the
// run really made.
#include <gtest/gtest.h>

#include "accuracy/live_estimate.hpp"
#include "physics/integrators/integrator.hpp"
#include "scenes.hpp"

namespace groundsim::accuracy {
namespace {

struct Watched {
  double estimate = 0.0;
  long long steps = 0, shadow_steps = 0;
  Trajectory run;
};

// prediction: the pilot's, as `groundsim run` gives it (0: windows alone)
Watched watch(const scenario::Scenario& s, int order, double prediction = 0.0, double growth = 0.0,
              double window_scale = 1.0) {
  Watched w;
  const scenario::Scene scene = scenario::buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  LiveEstimateOptions o;
  o.duration = s.duration;
  LiveEstimate live(s, order, o);
  live.setPrediction(prediction, s.duration, growth);
  live.setWindowScale(window_scale);
  const long long n = std::llround(s.duration / s.options.dt);
  for (long long i = 0; i < n; ++i) {
    live.beforeStep(sim);
    EXPECT_TRUE(scenario::stepScene(scene, sim, 1));
    live.afterStep(sim);
  }
  live.beforeStep(sim);
  w.estimate = live.estimate();
  w.steps = sim.state().tick;
  w.shadow_steps = live.shadowSteps();
  w.run = runTrajectory(s, s.duration);
  return w;
}

// The report's downhill at the settings the chooser takes for 1%, watched
// as `groundsim run` watches it: within a factor of 3 of the error made.
TEST(LiveEstimate, WithinAFactorOfThreeOnTheDownhill) {
  const scenario::Scenario base = test::config("downhill.json");
  const Choice c = chooseSettings(base, 0.01);
  const Watched w = watch(c.scenario, c.order, c.predicted_error, c.growth);
  const double truth = compareRuns(w.run, test::reference(base, 5e-6)).value();
  ASSERT_GT(truth, 1e-5);
  EXPECT_GT(w.estimate, truth / 3) << "truth " << truth << "; " << c.line();
  EXPECT_LT(w.estimate, truth * 3) << "truth " << truth << "; " << c.line();
}

// The windows alone see the error a step makes locally: on the sedan's
// slalom (no pilot) they come within a factor of 3 of the error made.
TEST(LiveEstimate, WindowsAloneWithinAFactorOfThreeOnTheSlalom) {
  const scenario::Scenario base = test::config("sedan_slalom.json", {"duration=6"});
  const scenario::Scenario s = withSettings(base, IntegratorKind::SemiImplicitEuler, 0.005);
  const Watched w = watch(s, 1);
  const double truth = compareRuns(w.run, test::reference(base, 0.02 / 64)).value();
  ASSERT_GT(truth, 1e-5);
  EXPECT_GT(w.estimate, truth / 3) << "truth " << truth;
  EXPECT_LT(w.estimate, truth * 3) << "truth " << truth;
}

// Its cost: two half steps in one window of 16, four windows in a run of
// known length, so 1/8 of the run's steps (the issue allows 15%).
TEST(LiveEstimate, ShadowStepsAreAnEighthOfTheRuns) {
  const scenario::Scenario s =
      withSettings(test::config("sedan_slalom.json", {"duration=4"}), IntegratorKind::SemiImplicitEuler, 0.005);
  const Watched w = watch(s, 1);
  EXPECT_GT(w.shadow_steps, 0);
  EXPECT_LE(static_cast<double>(w.shadow_steps), 0.15 * static_cast<double>(w.steps))
      << w.shadow_steps << " shadow steps for " << w.steps;
}

// A shadow that only watches changes nothing: the run with it is the run
// without it, bit for bit.
TEST(LiveEstimate, LeavesTheRunUntouched) {
  const scenario::Scenario s =
      withSettings(test::config("sedan_slalom.json", {"duration=3"}), IntegratorKind::VelocityVerlet, 0.005);
  const scenario::Scene scene = scenario::buildScene(s);
  Simulator watched(scene.built.model, scene.built.initial), plain(scene.built.model, scene.built.initial);
  LiveEstimate live(s, 2, LiveEstimateOptions{0.25, 2, 0.0});
  for (int i = 0; i < 600; ++i) {
    live.beforeStep(watched);
    scenario::stepScene(scene, watched, 1);
    live.afterStep(watched);
  }
  scenario::stepScene(scene, plain, 600);
  EXPECT_GT(live.windowsMeasured(), 0);
  EXPECT_EQ(watched.state().y, plain.state().y);
}

// The windows' calibration scales their reading, and nothing else.
TEST(LiveEstimate, TheWindowScaleScalesTheWindows) {
  const scenario::Scenario s =
      withSettings(test::config("sedan_slalom.json", {"duration=3"}), IntegratorKind::SemiImplicitEuler, 0.005);
  const Watched one = watch(s, 1), half = watch(s, 1, 0.0, 0.0, 0.5);
  ASSERT_GT(one.estimate, 0.0);
  EXPECT_DOUBLE_EQ(half.estimate, 0.5 * one.estimate);
}

// A pilot run watched as the run will be is the same run, and reads what
// the run's own windows read.
TEST(LiveEstimate, AWatchedPilotRunIsTheSameRun) {
  const scenario::Scenario s =
      withSettings(test::config("sedan_slalom.json", {"duration=3"}), IntegratorKind::SemiImplicitEuler, 0.005);
  const Trajectory plain = runTrajectory(s, s.duration), watched = runTrajectory(s, s.duration, 1);
  ASSERT_EQ(plain.positions.size(), watched.positions.size());
  for (size_t k = 0; k < plain.positions.size(); ++k) EXPECT_EQ(plain.positions[k], watched.positions[k]);
  EXPECT_EQ(plain.windows, -1.0);
  EXPECT_DOUBLE_EQ(watched.windows, watch(s, 1).estimate);
}

// On a scripted run the pilot ran whole, the calibrated windows read at
// most the error the pilot measured at the chosen step (their reading on
// the pilot's own run is that run's, so their scale brings it down to
// that error): the estimate at the end is the pilot's prediction.
TEST(LiveEstimate, CalibratedWindowsAgreeWithThePilotOnItsOwnRun) {
  const scenario::Scenario base = test::config("sedan_slalom.json", {"duration=8"});
  const Choice c = chooseSettings(base, 0.01);
  ASSERT_EQ(c.pilot_duration, base.duration);
  EXPECT_LE(c.window_scale, 1.0);
  const Watched w = watch(c.scenario, c.order, c.predicted_error, c.growth, c.window_scale);
  EXPECT_NEAR(w.estimate, c.predicted_error, 1e-9 * c.predicted_error) << c.line();
}

}  // namespace
}  // namespace groundsim::accuracy
