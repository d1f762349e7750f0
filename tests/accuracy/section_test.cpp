// The scenario's `accuracy` section: what it accepts and how it refuses.
#include <gtest/gtest.h>

#include "scenario/scenario.hpp"

namespace groundsim::scenario {
namespace {

nlohmann::json doc(nlohmann::json accuracy) {
  return {{"ground", {{"type", "plane"}}}, {"vehicle", nlohmann::json::object()}, {"accuracy", std::move(accuracy)}};
}

std::string firstIssue(const nlohmann::json& d) {
  try {
    parseScenario(d);
  } catch (const ScenarioError& e) {
    return e.issues().front().str();
  }
  return "";
}

TEST(Section, ReadsTheToleranceAndDefaults) {
  const Scenario s = parseScenario(doc({{"tolerance", 0.02}}));
  ASSERT_TRUE(s.accuracy.has_value());
  EXPECT_EQ(s.accuracy->tolerance, 0.02);
  EXPECT_EQ(s.accuracy->pilot_duration, AccuracySpec{}.pilot_duration);
  EXPECT_EQ(s.accuracy->pilot_share, 0.0);
  EXPECT_EQ(parseScenario(doc({{"tolerance", 0.02}, {"pilot_share", 0.2}})).accuracy->pilot_share, 0.2);
  EXPECT_TRUE(s.accuracy->live_estimate);
  EXPECT_TRUE(s.accuracy->refine);
  EXPECT_EQ(s.accuracy->max_refinements, 3);
  EXPECT_FALSE(parseScenario(nlohmann::json{{"ground", {{"type", "plane"}}}, {"vehicle", nlohmann::json::object()}})
                   .accuracy.has_value());
}

TEST(Section, NamesTheFieldAndTheReason) {
  EXPECT_EQ(firstIssue(doc({{"tolerance", 0}})).rfind("/accuracy/tolerance: must be", 0), 0u) << firstIssue(doc({{"tolerance", 0}}));
  EXPECT_EQ(firstIssue(doc({{"tolerance", 2}})).rfind("/accuracy/tolerance: must be", 0), 0u);
  EXPECT_EQ(firstIssue(doc({{"tolerance", "1%"}})).rfind("/accuracy/tolerance: expected a number", 0), 0u)
      << firstIssue(doc({{"tolerance", "1%"}}));
  EXPECT_EQ(firstIssue(doc({{"pilot_duration", 1e9}})).rfind("/accuracy/pilot_duration: must be", 0), 0u);
  EXPECT_EQ(firstIssue(doc({{"pilot_share", -0.1}})).rfind("/accuracy/pilot_share: must be", 0), 0u)
      << firstIssue(doc({{"pilot_share", -0.1}}));
  EXPECT_EQ(firstIssue(doc({{"tolerence", 0.1}})).rfind("/accuracy/tolerence: unknown key", 0), 0u)
      << firstIssue(doc({{"tolerence", 0.1}}));
  EXPECT_EQ(firstIssue(doc({{"max_refinements", 7}})).rfind("/accuracy/max_refinements: must be", 0), 0u)
      << firstIssue(doc({{"max_refinements", 7}}));
  EXPECT_EQ(firstIssue(doc({{"refine", 1}})).rfind("/accuracy/refine: expected", 0), 0u) << firstIssue(doc({{"refine", 1}}));
  EXPECT_EQ(firstIssue(doc(5)).rfind("/accuracy: expected an object", 0), 0u) << firstIssue(doc(5));
}

}  // namespace
}  // namespace groundsim::scenario
