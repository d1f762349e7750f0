// The task section's validation (scenario layer): JSON-pointer issues like
// every other section, defaults written back.
#include <gtest/gtest.h>

#include "scenario/scenario.hpp"
#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

std::vector<scenario::Issue> issuesOf(const nlohmann::json& doc) {
  try {
    scenario::parseScenario(doc);
  } catch (const scenario::ScenarioError& e) {
    return e.issues();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

::testing::AssertionResult has(const std::vector<scenario::Issue>& issues, const std::string& path,
                               const std::string& text) {
  for (const auto& i : issues)
    if (i.path == path && i.message.find(text) != std::string::npos) return ::testing::AssertionSuccess();
  std::string all;
  for (const auto& i : issues) all += "\n  " + i.str();
  return ::testing::AssertionFailure() << "no issue at " << path << " with '" << text << "' in" << all;
}

nlohmann::json road(nlohmann::json task) { return roadCarDoc(plane(), std::move(task)); }

TEST(TaskValidation, UnknownFeatureNamesItsIndexAndTheKnownOnes) {
  const auto issues = issuesOf(road({{"observation", {"speed", "time", "goal_distance", "velocty_body"}}, {"goal", {1, 2}}}));
  EXPECT_TRUE(has(issues, "/task/observation/3", "unknown feature \"velocty_body\"; known: position, heading"));
  EXPECT_TRUE(has(issues, "/task/observation/3", "velocity_body"));
}

TEST(TaskValidation, ObservationIsRequiredNonEmptyWithoutRepeats) {
  EXPECT_TRUE(has(issuesOf(road(nlohmann::json::object())), "/task/observation", "missing required key"));
  EXPECT_TRUE(has(issuesOf(road({{"observation", nlohmann::json::array()}})), "/task/observation", "at least one"));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed", "speed"}}})), "/task/observation/1", "listed twice"));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed", 3}}})), "/task/observation/1", "expected a feature name"));
}

TEST(TaskValidation, GoalTermsNeedAGoal) {
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"goal_body"}}})), "/task/goal", "need a goal"));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"goal", {1, 1}}, {"reward", {{"goal", 1}}}})),
                  "/task/termination", "goal_radius"));
}

TEST(TaskValidation, ActionsAndFeaturesMustSuitTheVehicle) {
  const auto report = reportCarDoc(plane(), {{"observation", {"speed", "suspension_travel"}}, {"action", {{"type", "car_controls"}}}});
  const auto issues = issuesOf(report);
  EXPECT_TRUE(has(issues, "/task/action/type", "needs a vehicle of kind \"road_car\""));
  EXPECT_TRUE(has(issues, "/task/observation/1", "needs a vehicle of kind \"road_car\""));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"vehicle", "truck"}})), "/task/vehicle",
                  "no vehicle named \"truck\""));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"action", {{"type", "wheel_torques"}, {"handbrake", true}}}})),
                  "/task/action/handbrake", "only with type"));
}

TEST(TaskValidation, RangesAndKeys) {
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"randomize", {{"x", {2, 1}}}}})), "/task/randomize/x",
                  "low <= high"));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"control_period", 0}})), "/task/control_period", ""));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"reward", {{"progres_to_goal", 1}}}})),
                  "/task/reward/progres_to_goal", "did you mean \"progress_to_goal\""));
  nlohmann::json params = {{"observation", {"speed"}}};
  params["randomize"]["parameters"] = {{{"path", "task.goal"}, {"range", {0, 1}}}};
  EXPECT_TRUE(has(issuesOf(road(params)),
                  "/task/randomize/parameters/0/path", "cannot be randomised"));
  nlohmann::json region = {{"observation", {"speed"}}};
  region["termination"]["region"] = {{"min", {0, 0}}, {"max", {0, 1}}};
  EXPECT_TRUE(has(issuesOf(road(region)),
                  "/task/termination/region/max", "must exceed min"));
  EXPECT_TRUE(has(issuesOf(road({{"observation", {"speed"}}, {"direction", {0, 0}}})), "/task/direction", "must not be"));
}

TEST(TaskValidation, DefaultsAreWrittenBackAndNoTaskMeansNone) {
  const auto s = scenario::parseScenario(road({{"observation", {"speed"}}}));
  ASSERT_TRUE(s.task.has_value());
  EXPECT_EQ(s.document["task"]["vehicle"], "sedan");
  EXPECT_EQ(s.document["task"]["control_period"], 1);
  EXPECT_EQ(s.document["task"]["action"]["type"], "car_controls");
  EXPECT_EQ(s.document["task"]["reward"]["alive"], 0.0);
  nlohmann::json doc = road({});
  doc.erase("task");
  EXPECT_FALSE(scenario::parseScenario(doc).task.has_value());
}

}  // namespace
}  // namespace groundsim::experiments::test
