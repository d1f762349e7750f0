// The shipped tasks are achievable: simple hand-written controllers reach
// goal.json's goal before its time limit, hold speed.json's target speed,
// and drive fast_car.json forward.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

float clamp1(double v, double lo = -1.0) { return static_cast<float>(std::clamp(v, lo, 1.0)); }

TEST(Tasks, ProportionalSteerToGoalReachesTheGoalBeforeTheTimeLimit) {
  Batch b(makeVecEnvFromFile(configPath("goal.json"), 4, {.num_threads = 2}));
  b.reset(2026);
  std::vector<int> ended(4, 0);
  const long long most = static_cast<long long>(std::ceil(b.layout().time_limit / (b.layout().dt * b.layout().control_period)));
  for (long long s = 0; s < most + 1 && std::count(ended.begin(), ended.end(), 0) > 0; ++s) {
    for (int e = 0; e < 4; ++e) {
      const double bearing = std::atan2(b.o("goal_body.y", e), b.o("goal_body.x", e));
      const double v = b.o("velocity_body.x", e);
      b.a(e)[0] = v < 8.0 ? 0.6f : 0.0f;  // throttle
      b.a(e)[1] = 0.0f;                  // brake
      b.a(e)[2] = clamp1(1.5 * bearing);  // steer (+ = left)
    }
    b.step();
    for (int e = 0; e < 4; ++e)
      if (!ended[e] && (b.term[e] || b.trunc[e])) {
        ended[e] = 1;
        EXPECT_EQ(b.term[e], 1) << "env " << e << " truncated";
        EXPECT_LE(b.o("goal_distance", e), 3.0) << "env " << e << " ended away from the goal";
        EXPECT_FALSE(b.env->info(e).diverged);
        EXPECT_GT(b.env->info(e).episode_return, 10.0);  // the goal bonus and the progress
      }
  }
  EXPECT_EQ(std::count(ended.begin(), ended.end(), 1), 4);
}

TEST(Tasks, ProportionalThrottleHoldsTheTargetSpeedOverBumps) {
  Batch b(makeVecEnvFromFile(configPath("speed.json"), 2, {.num_threads = 1}));
  b.reset(7);
  const double target = 15.0;
  double err = 0.0;
  int late = 0, s = 0;
  for (; s < 10000; ++s) {
    for (int e = 0; e < 2; ++e) {
      const double v = b.o("velocity_body.x", e);
      b.a(e)[0] = clamp1(0.5 * (target - v), 0.0);
      b.a(e)[1] = clamp1(0.5 * (v - target - 0.5), 0.0);
      b.a(e)[2] = clamp1(-3.0 * std::atan2(b.o("heading.sin", e), b.o("heading.cos", e)));
    }
    b.step();
    if (b.layout().dt * b.layout().control_period * (s + 1) > 10.0)
      for (int e = 0; e < 2; ++e, ++late) err += std::abs(b.o("velocity_body.x", e) - target);
    if (b.trunc[0] || b.term[0]) break;
  }
  EXPECT_EQ(b.trunc[0], 1);  // the time limit, not a fall
  EXPECT_EQ(b.term[0], 0);
  ASSERT_GT(late, 0);
  EXPECT_LT(err / late, 1.0) << "mean |v - 15 m/s| over the last 10 s";
  // speed tracking is near its maximum of 1 per action there
  EXPECT_GT(b.env->info(1).episode_return / (s + 1), 0.5);
}

TEST(Tasks, FastCarDrivesForwardUnderFullTorque) {
  Batch b(makeVecEnvFromFile(configPath("fast_car.json"), 2, {.num_threads = 1}));
  EXPECT_EQ(b.layout().control_period, 8);
  EXPECT_EQ(b.layout().actionSize(), 4);
  b.reset(1);
  b.setAll({1.0f, 1.0f, 1.0f, 1.0f});
  for (int s = 0; s < 200; ++s) {
    b.step();
    ASSERT_EQ(b.term[0], 0) << s;
  }
  EXPECT_GT(b.env->info(0).episode_return, 5.0);  // metres along +x, less the small effort penalty
}

}  // namespace
}  // namespace groundsim::experiments::test
