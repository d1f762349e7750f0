#include "scenario/scenario_error.hpp"

#include <cstdio>

namespace groundsim::scenario {
namespace {

void escapeInto(std::string& out, unsigned char c) {
  switch (c) {
    case '\n': out += "\\n"; return;
    case '\r': out += "\\r"; return;
    case '\t': out += "\\t"; return;
    default: break;
  }
  char buf[8];
  std::snprintf(buf, sizeof buf, "\\x%02x", c);
  out += buf;
}

bool control(unsigned char c) { return c < 0x20 || c == 0x7f; }

// Cut at a character boundary: never in the middle of a UTF-8 sequence.
std::size_t cutAt(const std::string& s, std::size_t n) {
  if (n >= s.size()) return s.size();
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  return n;
}

std::string lengthNote(std::size_t n) {
  std::string note = "... (";
  note += std::to_string(n);
  note += " bytes)";
  return note;
}

}  // namespace

std::string sanitized(const std::string& s, std::size_t max_chars) {
  const std::size_t end = cutAt(s, max_chars);
  std::string out;
  out.reserve(end + 16);
  for (std::size_t i = 0; i < end; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (control(c)) escapeInto(out, c);
    else out += static_cast<char>(c);
  }
  if (end < s.size()) out += lengthNote(s.size());
  return out;
}

std::string quote(const std::string& s, std::size_t max_chars) {
  const std::size_t end = cutAt(s, max_chars);
  std::string out = "\"";
  out.reserve(end + 24);
  for (std::size_t i = 0; i < end; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (control(c)) {
      escapeInto(out, c);
    } else {
      out += static_cast<char>(c);
    }
  }
  if (end < s.size()) out += lengthNote(s.size());
  out += '"';
  return out;
}

namespace {

std::string joined(const std::vector<Issue>& issues, std::size_t omitted, const std::string& sep) {
  std::string s;
  for (const Issue& i : issues) {
    if (!s.empty()) s += sep;
    s += i.str();
  }
  if (omitted > 0) {
    if (!s.empty()) s += sep;
    s += "and " + std::to_string(omitted) + " more problem" + (omitted == 1 ? "" : "s");
  }
  return s.empty() ? std::string("invalid scenario") : s;
}

}  // namespace

namespace {

// A list given directly (not through IssueList) is capped and cleaned the
// same way; the bounds are above IssueList's, so cleaning twice changes nothing.
std::vector<Issue> capped(std::vector<Issue> issues, std::size_t* omitted) {
  if (issues.size() > kMaxListedIssues) {
    *omitted += issues.size() - kMaxListedIssues;
    issues.resize(kMaxListedIssues);
  }
  for (Issue& i : issues) {
    i.path = sanitized(i.path, 5 * kMaxQuotedChars);
    i.message = sanitized(i.message, 6 * kMaxQuotedChars);
  }
  return issues;
}

}  // namespace

ScenarioError::ScenarioError(std::vector<Issue> issues, std::size_t omitted)
    : ScenarioError(capped(std::move(issues), &omitted), omitted, 0) {}

ScenarioError::ScenarioError(std::vector<Issue> issues, std::size_t omitted, int)
    : std::runtime_error(joined(issues, omitted, "\n")), issues_(std::move(issues)), omitted_(omitted) {}

std::string ScenarioError::lines(const std::string& separator) const {
  return joined(issues_, omitted_, separator);
}

}  // namespace groundsim::scenario
