// Helpers shared by the scenario tests: a minimal valid document and
// assertions on the issues a ScenarioError lists.
#pragma once

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "scenario/scenario.hpp"

namespace groundsim::scenario::test {

// The smallest valid scenario: every other key takes its default.
inline nlohmann::json minimalDoc() {
  return nlohmann::json::parse(R"({"ground": {"type": "plane"}, "vehicle": {}})");
}

// Text with the budget to parse it under (issuesOf(parseScenarioText(t, b))).
struct TextWithBudget {
  std::string text;
  Budget budget;
};
inline TextWithBudget parseScenarioText(std::string text, Budget budget) { return {std::move(text), std::move(budget)}; }

// The issues parseScenario reports; fails the test when it accepts the document.
template <class Input>
std::vector<Issue> issuesOf(const Input& input) {
  try {
    if constexpr (std::is_same_v<Input, TextWithBudget>) parseScenario(input.text, input.budget);
    else parseScenario(input);
  } catch (const ScenarioError& e) {
    return e.issues();
  }
  ADD_FAILURE() << "document was accepted";
  return {};
}

// The error parseScenario throws (its issues, omitted count and what()).
template <class Input>
std::optional<ScenarioError> errorOf(const Input& input, const Budget& budget = Budget{}) {
  try {
    parseScenario(input, budget);
  } catch (const ScenarioError& e) {
    return e;
  }
  return std::nullopt;
}

inline std::string listed(const std::vector<Issue>& issues) {
  std::string s;
  for (const Issue& i : issues) s += "\n  " + i.str();
  return s;
}

// An issue at exactly `path` whose message contains `text`.
inline ::testing::AssertionResult hasIssue(const std::vector<Issue>& issues, const std::string& path,
                                           const std::string& text = "") {
  for (const Issue& i : issues)
    if (i.path == path && i.message.find(text) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "no issue at \"" << path << "\" containing \"" << text
                                       << "\"; got:" << listed(issues);
}

}  // namespace groundsim::scenario::test
