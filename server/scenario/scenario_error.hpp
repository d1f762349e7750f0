// Collecting validation problems. Issue and ScenarioError are declared in
// scenario.hpp (the public API); this header adds the list the readers
// append to while a document is validated.
#pragma once

#include <string>
#include <vector>

#include "scenario/scenario.hpp"

namespace groundsim::scenario {

class IssueList {
 public:
  void add(std::string path, std::string message) { list_.push_back({std::move(path), std::move(message)}); }
  bool empty() const { return list_.empty(); }
  size_t size() const { return list_.size(); }
  const std::vector<Issue>& items() const { return list_; }
  // Throws ScenarioError when anything was recorded.
  void throwIfAny() const {
    if (!list_.empty()) throw ScenarioError(list_);
  }

 private:
  std::vector<Issue> list_;
};

}  // namespace groundsim::scenario
