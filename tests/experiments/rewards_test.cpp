// Each reward term against its formula (docs/scenario.md, "Tasks"), one
// term weighted at a time, computed from the observations before and after
// the action; and the total as the weighted sum.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

nlohmann::json task(nlohmann::json reward) {
  return {{"observation", {"position", "velocity_body", "up_body", "goal_distance"}},
          {"goal", {30.0, 10.0}},
          {"reward", std::move(reward)}};
}

Batch moving(nlohmann::json t, nlohmann::json ground = plane()) {
  return Batch(roadCarDoc(std::move(ground), std::move(t), {{"speed", 5.0}, {"yaw_deg", 10.0}}), 1);
}

TEST(Rewards, ProgressToGoalIsTheShrinkOfTheGoalDistance) {
  Batch b = moving(task({{"progress_to_goal", 1.0}}));
  b.reset();
  const double before = b.o("goal_distance");
  b.step();
  EXPECT_GT(b.rew[0], 0.01);
  EXPECT_NEAR(b.rew[0], before - b.o("goal_distance"), 1e-5);
}

TEST(Rewards, ProgressAlongIsTheDisplacementAlongTheDirection) {
  nlohmann::json t = task({{"progress_along", 2.0}});
  t["direction"] = {3.0, 4.0};  // normalised to (0.6, 0.8)
  Batch b = moving(t);
  b.reset();
  const double x0 = b.o("position.x"), y0 = b.o("position.y");
  b.step();
  EXPECT_NEAR(b.rew[0], 2.0 * (0.6 * (b.o("position.x") - x0) + 0.8 * (b.o("position.y") - y0)), 1e-5);
}

TEST(Rewards, SpeedTrackingIsAGaussianOfTheForwardSpeedError) {
  nlohmann::json t = task({{"speed_tracking", 1.0}});
  t["target_speed"] = 4.0;
  t["speed_tolerance"] = 2.0;
  Batch b = moving(t);
  b.reset();
  b.step();
  const double e = (b.o("velocity_body.x") - 4.0) / 2.0;
  EXPECT_NEAR(b.rew[0], std::exp(-e * e), 1e-6);
  EXPECT_LT(b.rew[0], 1.0);
}

TEST(Rewards, EffortAndJerkAreMeanSquaresOfTheNormalisedAction) {
  Batch b = moving(task({{"effort", 1.0}}));
  b.reset();
  b.setAll({0.5f, 0.25f, -0.75f});
  b.step();
  EXPECT_DOUBLE_EQ(b.rew[0], -(0.25 + 0.0625 + 0.5625) / 3.0);

  Batch j = moving(task({{"jerk", 3.0}}));
  j.reset();
  j.setAll({0.5f, 0.25f, -0.75f});
  j.step();  // from the zero action of the reset
  EXPECT_DOUBLE_EQ(j.rew[0], -3.0 * (0.25 + 0.0625 + 0.5625) / 3.0);
  j.setAll({0.25f, 0.25f, 0.25f});
  j.step();
  EXPECT_DOUBLE_EQ(j.rew[0], -3.0 * (0.0625 + 0.0 + 1.0) / 3.0);
}

TEST(Rewards, WheelTorquesAreNormalisedByTheirMaximum) {
  nlohmann::json t = task({{"effort", 1.0}});
  t.erase("goal");
  t["observation"] = {"speed"};
  t["action"] = {{"type", "wheel_torques"}, {"max_torque", 4.0}};
  Batch b(reportCarDoc(plane(), t), 1);
  b.reset();
  b.setAll({2.0f, -2.0f, 4.0f, 0.0f});
  b.step();
  EXPECT_DOUBLE_EQ(b.rew[0], -(0.25 + 0.25 + 1.0 + 0.0) / 4.0);
}

TEST(Rewards, TiltIsOneMinusTheCosineOfTheTilt) {
  Batch b = moving(task({{"tilt", 1.0}}), {{"type", "incline"}, {"angle_deg", 10.0}, {"downhill", {0.0, 1.0}}});
  b.reset();
  b.step();
  EXPECT_NEAR(b.rew[0], -(1.0 - b.o("up_body.z")), 1e-6);
  EXPECT_NEAR(b.rew[0], -(1.0 - std::cos(10.0 * std::numbers::pi / 180.0)), 2e-3);
}

TEST(Rewards, AliveBonusAndTheWeightedSum) {
  Batch b = moving(task({{"alive", 2.5}, {"effort", 0.5}}));
  b.reset();
  b.setAll({1.0f, 0.0f, 0.0f});
  b.step();
  EXPECT_DOUBLE_EQ(b.rew[0], 2.5 - 0.5 * (1.0 / 3.0));
}

TEST(Rewards, GoalBonusOnTheActionThatReachesTheGoal) {
  nlohmann::json t = task({{"goal", 7.0}});
  t["goal"] = {0.5, 0.0};
  t["termination"] = {{"goal_radius", 2.0}};
  Batch b = moving(t);
  b.reset();
  b.step();
  EXPECT_EQ(b.rew[0], 7.0);
  EXPECT_EQ(b.term[0], 1);
  EXPECT_EQ(b.trunc[0], 0);
}

}  // namespace
}  // namespace groundsim::experiments::test
