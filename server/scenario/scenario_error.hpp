// Collecting validation problems. Issue and ScenarioError are declared in
// scenario.hpp (the public API); this header adds the list the readers
// append to while a document is validated.
#pragma once

#include <string>
#include <vector>

#include "scenario/scenario.hpp"

namespace groundsim::scenario {

// Escapes control characters (and nothing else) and cuts to max_chars:
// the last defence of every message against raw or huge user text.
std::string sanitized(const std::string& s, std::size_t max_chars);

// Keeps the first kMaxListedIssues problems and counts the rest, so that a
// document with a million problems costs a million counts, not a million
// messages.
class IssueList {
 public:
  // paths hold user keys: both are sanitized and cut (user strings in
  // messages are already quote(), this is the backstop)
  void add(std::string path, std::string message) {
    ++count_;
    if (list_.size() < kMaxListedIssues)
      list_.push_back({sanitized(path, 4 * kMaxQuotedChars), sanitized(message, 5 * kMaxQuotedChars)});
  }
  bool empty() const { return count_ == 0; }
  std::size_t size() const { return count_; }
  // the listing is full: callers may stop looking for more
  bool full() const { return count_ >= kMaxListedIssues; }
  const std::vector<Issue>& items() const { return list_; }
  // Throws ScenarioError when anything was recorded.
  void throwIfAny() const {
    if (count_ > 0) throw ScenarioError(list_, count_ - list_.size());
  }

 private:
  std::vector<Issue> list_;
  std::size_t count_ = 0;
};

}  // namespace groundsim::scenario
