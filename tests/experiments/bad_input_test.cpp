// Bad calls: NaN and infinite actions (refused, naming actions[i][j], with
// nothing stepped), out-of-range actions (clipped), seeds, env indices,
// sizes and null buffers.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

nlohmann::json task() { return {{"observation", {"position", "previous_action"}}}; }

std::string fieldOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ExperimentError& e) {
    return e.field();
  }
  return "(accepted)";
}

TEST(BadInput, NonFiniteActionsAreRefusedByIndexAndNothingSteps) {
  Batch b(roadCarDoc(plane(), task(), {{"speed", 3.0}}), 3);
  b.reset();
  const std::vector<float> before = b.obs;
  b.a(2)[1] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(fieldOf([&] { b.step(); }), "actions[2][1]");
  b.a(2)[1] = 0.0f;
  b.a(0)[2] = -std::numeric_limits<float>::infinity();
  try {
    b.step();
    ADD_FAILURE() << "accepted";
  } catch (const ExperimentError& e) {
    EXPECT_EQ(e.field(), "actions[0][2]");
    EXPECT_NE(std::string(e.what()).find("-inf"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("steer"), std::string::npos);
  }
  EXPECT_EQ(b.obs, before);
  for (int e = 0; e < 3; ++e) EXPECT_EQ(b.env->info(e).episode_steps, 0);
}

TEST(BadInput, FiniteActionsAreClippedToTheBounds) {
  nlohmann::json t = task();
  t["action"] = {{"type", "wheel_torques"}, {"max_torque", 2.0}};
  Batch b(reportCarDoc(plane(), t), 1);
  b.reset();
  b.setAll({1e30f, -5.0f, 1.5f, -1e-3f});
  b.step();
  EXPECT_EQ(b.o("previous_action.drive_torque.fl"), 2.0f);
  EXPECT_EQ(b.o("previous_action.drive_torque.fr"), -2.0f);
  EXPECT_EQ(b.o("previous_action.drive_torque.rl"), 1.5f);
  EXPECT_EQ(b.o("previous_action.drive_torque.rr"), -1e-3f);
}

TEST(BadInput, SeedsEnvIndicesCountsAndBuffers) {
  Batch b(roadCarDoc(plane(), task()), 2);
  EXPECT_EQ(fieldOf([&] { b.env->reset(1ull << 63, b.obs.data()); }), "seed");
  EXPECT_EQ(fieldOf([&] { b.env->reset((1ull << 63) - 1, b.obs.data()); }), "(accepted)");
  EXPECT_EQ(fieldOf([&] { b.env->resetEnv(2, 0, b.obs.data()); }), "env");
  EXPECT_EQ(fieldOf([&] { b.env->resetEnv(-1, 0, b.obs.data()); }), "env");
  EXPECT_EQ(fieldOf([&] { b.env->info(2); }), "row");  // info is per row (environment x agent)
  EXPECT_EQ(fieldOf([&] { b.env->snapshot(-1); }), "env");
  EXPECT_EQ(fieldOf([&] { b.env->restore(5, "", b.obs.data()); }), "env");
  EXPECT_EQ(fieldOf([&] { b.env->step(nullptr, b.obs.data(), b.rew.data(), b.term.data(), b.trunc.data()); }),
            "actions");
  EXPECT_EQ(fieldOf([&] { b.env->reset(0, nullptr); }), "obs");
  const std::string doc = roadCarDoc(plane(), task()).dump();
  EXPECT_EQ(fieldOf([&] { makeVecEnv(doc, 0); }), "num_envs");
  EXPECT_EQ(fieldOf([&] { makeVecEnv(doc, 5, {.max_envs = 4}); }), "num_envs");
  EXPECT_EQ(fieldOf([&] { makeVecEnv(doc, 1, {.num_threads = -1}); }), "num_threads");
}

TEST(BadInput, AScenarioWithoutATaskOrWithABadOneIsAScenarioError) {
  nlohmann::json doc = roadCarDoc(plane(), task());
  doc.erase("task");
  try {
    makeVecEnv(doc.dump(), 1);
    ADD_FAILURE() << "accepted";
  } catch (const scenario::ScenarioError& e) {
    EXPECT_EQ(e.issues().at(0).path, "/task");
  }
  nlohmann::json t = task();
  t["randomize"] = {{"parameters", {{{"path", "vehicle.mass"}, {"range", {-5.0, 1000.0}}}}}};
  try {
    makeVecEnv(roadCarDoc(plane(), t).dump(), 1);
    ADD_FAILURE() << "accepted";
  } catch (const scenario::ScenarioError& e) {
    EXPECT_EQ(e.issues().at(0).path, "/task/randomize/parameters/0/range");
    EXPECT_NE(e.issues().at(0).message.find("/vehicle/mass"), std::string::npos) << e.what();
  }
}

TEST(BadInput, OneBatchedStepIsBoundedByTheWorkBudget) {
  nlohmann::json t = task();
  t["control_period"] = 100000;
  scenario::Budget small;
  small.max_work = 1e9;
  try {
    makeVecEnv(roadCarDoc(plane(), t).dump(), 4096, {.budget = small});
    ADD_FAILURE() << "accepted";
  } catch (const scenario::ScenarioError& e) {
    EXPECT_EQ(e.issues().at(0).path, "/task/control_period");
    EXPECT_NE(e.issues().at(0).message.find("--max-work"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace groundsim::experiments::test
