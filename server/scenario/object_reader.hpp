// Reading one JSON object of a scenario while validating it.
//
// An ObjectReader wraps an object inside the document being validated. Each
// accessor reads one key with its type and range, records any problem as an
// Issue under the key's JSON pointer path and carries on (so a user sees
// every problem at once, not one per run), and writes the default back when
// the key is absent, so that the document ends complete: the exact record of
// what was simulated. finish() reports every key nobody asked for as unknown,
// with the closest known key as a hint: a misspelt key must never be
// silently ignored, since it would leave a default in place unnoticed.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physics/base/math.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::scenario {

// Every number in a scenario is bounded, so that arithmetic on it (masses
// times g, stiffness times depth) stays finite: 1e308 kg is a typo, not a car.
inline constexpr double kMaxMagnitude = 1e9;
// The smallest physics.dt (s).
inline constexpr double kMinDt = 1e-9;

// Allowed interval for a number; each end open or closed.
struct Range {
  double lo = -kMaxMagnitude, hi = kMaxMagnitude;
  bool lo_open = false, hi_open = false;

  static Range any() { return {}; }
  static Range positive(double hi = kMaxMagnitude) { return {0.0, hi, true, false}; }
  static Range nonNegative(double hi = kMaxMagnitude) { return {0.0, hi, false, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, false, false}; }
  // The reason v is outside, or nullopt when it is inside.
  std::optional<std::string> violation(double v) const;
};

// A number as short readable text (%g; DBL_MAX is "1.79769e+308"): the one
// formatter of numbers in messages (net::number and the sessions use it).
std::string formatNumber(double v);
// "number", "string", "object", ... as a user reads them.
std::string jsonTypeName(const nlohmann::json& v);
// Escapes a key for a JSON pointer (RFC 6901: ~ -> ~0, / -> ~1).
std::string pointerToken(const std::string& key);
// The known key closest to `key` by edit distance, when close enough to be
// a plausible typo; empty otherwise.
std::string closestKey(const std::string& key, const std::vector<std::string>& known);

class ObjectReader {
 public:
  // obj must outlive the reader. A non-object is reported once here; the
  // accessors then return defaults without further issues.
  ObjectReader(nlohmann::json& obj, std::string path, IssueList& issues);

  bool valid() const { return valid_; }
  const std::string& path() const { return path_; }
  std::string pathOf(const std::string& key) const { return path_ + "/" + pointerToken(key); }
  IssueList& issues() { return *issues_; }
  bool has(const std::string& key) const;
  // The value at key as it is, without reading it (nullptr when absent).
  const nlohmann::json* peek(const std::string& key) const;
  // Marks a key as known without reading it (read elsewhere).
  void allow(const std::string& key);
  void issue(const std::string& key, std::string message) { issues_->add(pathOf(key), std::move(message)); }

  double number(const std::string& key, double def, Range range = Range::any());
  // A number with no default: reported as missing when absent.
  std::optional<double> requiredNumber(const std::string& key, Range range = Range::any());
  int integer(const std::string& key, int def, int lo, int hi);
  bool boolean(const std::string& key, bool def);
  std::string string(const std::string& key, const std::string& def);
  std::optional<std::string> requiredString(const std::string& key);
  // One of `allowed`; the message lists them.
  std::string choice(const std::string& key, const std::string& def, const std::vector<std::string>& allowed);
  std::optional<std::string> requiredChoice(const std::string& key, const std::vector<std::string>& allowed);
  // A fixed-length array of numbers, each in range.
  Eigen::VectorXd vector(const std::string& key, const Eigen::VectorXd& def, Range each = Range::any());
  Vec3 vec3(const std::string& key, const Vec3& def, Range each = Range::any());
  // An array for the caller to read element by element (type checked), or
  // nullptr when absent or not an array.
  nlohmann::json* array(const std::string& key);
  // A nested object; created empty when absent (its readers fill defaults).
  ObjectReader object(const std::string& key);
  // An array of numbers of length [min_len, max_len], each in range.
  std::vector<double> numbers(const std::string& key, const std::vector<double>& def, Range each, size_t min_len,
                              size_t max_len);
  // An array of objects (absent: none), one reader per element.
  std::vector<ObjectReader> objects(const std::string& key);

  // Reports every key that no accessor asked for.
  void finish();

 private:
  // obj == nullptr: the reader of a key inside a non-object, silently empty
  ObjectReader(nlohmann::json* obj, std::string path, IssueList& issues);
  // The value at key after the type check, or nullptr (absent or wrong type,
  // the latter reported).
  nlohmann::json* get(const std::string& key, bool (nlohmann::json::*is)() const noexcept,
                      const char* expected);
  std::optional<double> checkedNumber(const std::string& key, const nlohmann::json& v, const Range& r);
  // The number at `path` (an array element's own path), or nullopt with the
  // problem reported there: type, the global magnitude bound, then the range.
  std::optional<double> checkedAt(const std::string& path, const nlohmann::json& v, const Range& r);

  nlohmann::json* obj_;
  std::string path_;
  IssueList* issues_;
  bool valid_ = false;
  std::vector<std::string> known_;
};

}  // namespace groundsim::scenario
