// Episodes: termination (tilt, region, goal, divergence), truncation at the
// time limit, and the NEXT_STEP autoreset sequence of batch_env.hpp.
#include <gtest/gtest.h>

#include <cmath>

#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

nlohmann::json task() {
  return {{"observation", {"position", "time", "speed"}}, {"reward", {{"alive", 1.0}}}};
}

TEST(Episodes, TruncatedAtTheTimeLimitInWholeActions) {
  nlohmann::json t = task();
  t["control_period"] = 5;
  t["time_limit"] = 0.1;  // 0.1 / (5 * 0.004) = 5 actions
  Batch b(roadCarDoc(plane(), t), 1);
  b.reset();
  for (int i = 1; i <= 5; ++i) {
    b.step();
    EXPECT_EQ(b.term[0], 0) << i;
    EXPECT_EQ(b.trunc[0], i == 5 ? 1 : 0) << i;
  }
  EXPECT_EQ(b.env->info(0).episode_steps, 5);
  EXPECT_DOUBLE_EQ(b.env->info(0).episode_return, 5.0);
}

TEST(Episodes, AutoresetOnTheNextStepIgnoresItsAction) {
  nlohmann::json t = task();
  t["time_limit"] = 0.008;  // two actions
  t["randomize"] = {{"x", {-5.0, 5.0}}};
  Batch b(roadCarDoc(plane(), t, {{"speed", 3.0}}), 1);
  b.reset(42);
  EXPECT_EQ(b.env->info(0).episode, 1);
  b.setAll({1.0f, 0.0f, 0.0f});
  b.step();
  b.step();
  ASSERT_EQ(b.trunc[0], 1);
  const double x_end = b.o("position.x");
  // the next step: the first observation of episode 2, reward 0, no flags
  b.step();
  EXPECT_EQ(b.rew[0], 0.0);
  EXPECT_EQ(b.term[0], 0);
  EXPECT_EQ(b.trunc[0], 0);
  EXPECT_EQ(b.o("time"), 0.0);
  EXPECT_NE(b.o("position.x"), x_end);
  const EnvInfo i = b.env->info(0);
  EXPECT_EQ(i.episode, 2);
  EXPECT_EQ(i.episode_steps, 0);
  EXPECT_EQ(i.episode_return, 0.0);
  // it is the same first observation as a reset of the same stream: a
  // second batch seeded alike, reset twice
  Batch c(roadCarDoc(plane(), t, {{"speed", 3.0}}), 1);
  c.reset(42);
  c.env->reset(std::nullopt, c.obs.data());
  EXPECT_EQ(c.obs, b.obs);
  // and the episode goes on from there
  b.step();
  EXPECT_EQ(b.rew[0], 1.0);
  EXPECT_EQ(b.env->info(0).episode_steps, 1);
}

TEST(Episodes, BeforeAnyResetTheFirstStepStartsEpisodeOne) {
  Batch b(roadCarDoc(plane(), task()), 1);
  EXPECT_EQ(b.env->info(0).episode, 0);
  b.step();
  EXPECT_EQ(b.env->info(0).episode, 1);
  EXPECT_EQ(b.rew[0], 0.0);
}

TEST(Episodes, TiltBeyondTheLimitTerminates) {
  nlohmann::json t = task();
  t["termination"] = {{"max_tilt_deg", 5.0}};
  Batch steep(roadCarDoc({{"type", "incline"}, {"angle_deg", 8.0}}, t), 1);
  steep.reset();
  steep.step();
  EXPECT_EQ(steep.term[0], 1);
  Batch gentle(roadCarDoc({{"type", "incline"}, {"angle_deg", 3.0}}, t), 1);
  gentle.reset();
  gentle.step();
  EXPECT_EQ(gentle.term[0], 0);
}

TEST(Episodes, LeavingTheRegionTerminates) {
  nlohmann::json t = task();
  t["termination"] = {{"region", {{"min", {-10.0, -10.0}}, {"max", {0.05, 10.0}}}}};
  Batch b(roadCarDoc(plane(), t, {{"speed", 5.0}}), 1);  // 2 cm per action along +x
  b.reset();
  int steps = 0;
  while (!b.term[0] && steps < 10) {
    b.step();
    ++steps;
    if (!b.term[0]) {
      EXPECT_LE(b.o("position.x"), 0.05);
    }
  }
  EXPECT_EQ(b.term[0], 1);
  EXPECT_GT(b.o("position.x"), 0.05);
  EXPECT_GE(steps, 2);
}

TEST(Episodes, DivergenceTerminatesAndPublishesTheLastFiniteState) {
  nlohmann::json doc = roadCarDoc(plane(), task(), {{"speed", 5.0}});
  doc["physics"]["limits"] = {{"max_speed", 4.0}};  // exceeded on the first step
  Batch b(doc, 1);
  b.reset();
  b.step();
  EXPECT_EQ(b.term[0], 1);
  EXPECT_TRUE(b.env->info(0).diverged);
  for (float v : b.obs) EXPECT_TRUE(std::isfinite(v));
  EXPECT_NEAR(b.o("speed"), 5.0, 1e-4);  // the state before the step
  b.step();  // autoreset: a healthy new episode
  EXPECT_FALSE(b.env->info(0).diverged);
  EXPECT_EQ(b.env->info(0).episode, 2);
}

}  // namespace
}  // namespace groundsim::experiments::test
