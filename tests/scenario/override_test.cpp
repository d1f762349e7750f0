// `--set key.path=value`: applied to the raw document, then validated.
#include <gtest/gtest.h>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

TEST(Override, SetsANumber) {
  auto d = minimalDoc();
  applyOverride(d, "vehicle.wheel_radius=0.5");
  EXPECT_EQ(parseScenario(d).vehicles[0].params.wheel_radius, 0.5);
}

TEST(Override, CreatesMissingSections) {
  auto d = minimalDoc();
  applyOverride(d, "physics.dt=1e-4");
  EXPECT_EQ(parseScenario(d).options.dt, 1e-4);
}

TEST(Override, ValueIsJsonWhenItParsesElseText) {
  auto d = minimalDoc();
  applyOverride(d, "physics.gravity=[0,0,-1.62]");
  applyOverride(d, "vehicle.body_contact=false");
  applyOverride(d, "vehicle.name=moon_rover");
  const Scenario s = parseScenario(d);
  EXPECT_EQ(s.options.gravity.z(), -1.62);
  EXPECT_FALSE(s.vehicles[0].params.body_contact);
  EXPECT_EQ(s.vehicles[0].name, "moon_rover");
}

TEST(Override, ArrayIndex) {
  auto d = nlohmann::json::parse(
      R"({"ground": {"type": "plane"}, "vehicles": [{"name": "a"}, {"name": "b", "initial": {"position": [20, 0, 0]}}]})");
  applyOverride(d, "vehicles.1.wheel_radius=0.8");
  applyOverride(d, "vehicles.1.initial.position.1=5");
  const Scenario s = parseScenario(d);
  EXPECT_EQ(s.vehicles[1].params.wheel_radius, 0.8);
  EXPECT_EQ(s.vehicles[1].placement.position.y(), 5.0);
  EXPECT_EQ(s.vehicles[0].params.wheel_radius, CarParams{}.wheel_radius);
}

TEST(Override, InvalidValueIsReportedByValidation) {
  auto d = minimalDoc();
  applyOverride(d, "vehicle.wheel_radius=-1");
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/wheel_radius", "must be > 0"));
  d = minimalDoc();
  applyOverride(d, "vehicle.wheel_radus=1");
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/wheel_radus", "did you mean \"wheel_radius\""));
}

std::vector<Issue> overrideIssues(nlohmann::json d, const std::string& a) {
  try {
    applyOverride(d, a);
  } catch (const ScenarioError& e) {
    return e.issues();
  }
  ADD_FAILURE() << a << " was accepted";
  return {};
}

TEST(Override, BadPathsNameTheKey) {
  auto d = minimalDoc();
  d["vehicles"] = nlohmann::json::array({nlohmann::json::object()});
  EXPECT_TRUE(hasIssue(overrideIssues(d, "no_equals_sign"), "", "key.path=value"));
  EXPECT_TRUE(hasIssue(overrideIssues(d, "=3"), "", "key.path=value"));
  EXPECT_TRUE(hasIssue(overrideIssues(d, "vehicle..x=3"), "", "empty key segment"));
  EXPECT_TRUE(hasIssue(overrideIssues(d, "vehicles.4.name=x"), "/vehicles/4", "past the end"));
  EXPECT_TRUE(hasIssue(overrideIssues(d, "vehicles.first.name=x"), "/vehicles/first", "array index"));
  d["duration"] = 3;
  EXPECT_TRUE(hasIssue(overrideIssues(d, "duration.x=1"), "/duration/x", "inside a value of type integer"));
}

}  // namespace
}  // namespace groundsim::scenario::test
