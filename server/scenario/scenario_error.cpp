#include "scenario/scenario.hpp"

namespace groundsim::scenario {
namespace {

// One issue per line: what() is what a user reads when nothing else formats it.
std::string joined(const std::vector<Issue>& issues) {
  std::string s;
  for (const Issue& i : issues) {
    if (!s.empty()) s += '\n';
    s += i.str();
  }
  return s.empty() ? std::string("invalid scenario") : s;
}

}  // namespace

ScenarioError::ScenarioError(std::vector<Issue> issues)
    : std::runtime_error(joined(issues)), issues_(std::move(issues)) {}

}  // namespace groundsim::scenario
