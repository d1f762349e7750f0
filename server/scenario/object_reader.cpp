#include "scenario/object_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace groundsim::scenario {

// %g: 6 significant digits, so DBL_MAX reads 1.79769e+308, not 309 digits
std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string jsonTypeName(const nlohmann::json& v) {
  if (v.is_number_integer() || v.is_number_unsigned()) return "integer";
  if (v.is_number()) return "number";
  return v.type_name();  // "string", "object", "array", "boolean", "null"
}

std::string pointerToken(const std::string& key) {
  // a key is user text: cut like any quoted string (IssueList escapes)
  const std::string k = key.size() > kMaxQuotedChars ? sanitized(key, kMaxQuotedChars) : key;
  std::string out;
  for (char c : k) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

namespace {

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string closestKey(const std::string& key, const std::vector<std::string>& known) {
  // the distance costs |key| x |known key|: no typo of a short key is long
  if (key.size() > 64) return {};
  std::string best;
  size_t best_d = std::string::npos;
  for (const std::string& k : known) {
    const size_t d = editDistance(key, k);
    if (d < best_d) best_d = d, best = k;
  }
  // a third of the length, at least 1 and at most 3 edits: "whel_radius"
  // finds "wheel_radius", "x" does not find "dt"
  const size_t allowed = std::clamp<size_t>(std::max(key.size(), best.size()) / 3, 1, 3);
  return best_d <= allowed ? best : std::string();
}

std::optional<std::string> Range::violation(double v) const {
  if (!std::isfinite(v)) return "must be finite, got " + formatNumber(v);
  if (lo_open ? !(v > lo) : !(v >= lo))
    return std::string("must be ") + (lo_open ? "> " : ">= ") + formatNumber(lo) + ", got " + formatNumber(v);
  if (hi_open ? !(v < hi) : !(v <= hi))
    return std::string("must be ") + (hi_open ? "< " : "<= ") + formatNumber(hi) + ", got " + formatNumber(v);
  return std::nullopt;
}

ObjectReader::ObjectReader(nlohmann::json& obj, std::string path, IssueList& issues)
    : ObjectReader(&obj, std::move(path), issues) {}

bool ObjectReader::has(const std::string& key) const { return valid_ && obj_->contains(key); }

void ObjectReader::allow(const std::string& key) { known_.push_back(key); }

nlohmann::json* ObjectReader::get(const std::string& key, bool (nlohmann::json::*is)() const noexcept,
                                  const char* expected) {
  known_.push_back(key);
  if (!valid_) return nullptr;
  auto it = obj_->find(key);
  if (it == obj_->end()) return nullptr;
  if (!((*it).*is)()) {
    issue(key, std::string("expected ") + expected + ", got " + jsonTypeName(*it));
    return nullptr;
  }
  return &*it;
}

std::optional<double> ObjectReader::checkedAt(const std::string& path, const nlohmann::json& v, const Range& r) {
  if (!v.is_number()) {
    issues_->add(path, "expected a number, got " + jsonTypeName(v));
    return std::nullopt;
  }
  const double x = v.get<double>();
  // the global magnitude bound first: it names the real reason for 1e308
  if (std::isfinite(x) && std::abs(x) > kMaxMagnitude) {
    issues_->add(path, "must be at most " + formatNumber(kMaxMagnitude) + " in magnitude, got " + formatNumber(x));
    return std::nullopt;
  }
  if (auto why = r.violation(x)) {
    issues_->add(path, *why);
    return std::nullopt;
  }
  return x;
}

std::optional<double> ObjectReader::checkedNumber(const std::string& key, const nlohmann::json& v, const Range& r) {
  return checkedAt(pathOf(key), v, r);
}

double ObjectReader::number(const std::string& key, double def, Range range) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_number, "a number");
  if (!v) {
    if (!present && valid_) (*obj_)[key] = def;
    return def;
  }
  return checkedNumber(key, *v, range).value_or(def);
}

std::optional<double> ObjectReader::requiredNumber(const std::string& key, Range range) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_number, "a number");
  if (!present && valid_) issue(key, "missing required key (a number)");
  if (!v) return std::nullopt;
  return checkedNumber(key, *v, range);
}

int ObjectReader::integer(const std::string& key, int def, int lo, int hi) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_number, "an integer");
  if (!v) {
    if (!present && valid_) (*obj_)[key] = def;
    return def;
  }
  const double x = v->get<double>();
  if (!std::isfinite(x) || x != std::floor(x)) {
    issue(key, "expected an integer, got " + formatNumber(x));
    return def;
  }
  if (auto why = Range::closed(lo, hi).violation(x)) {
    issue(key, *why);
    return def;
  }
  return static_cast<int>(x);
}

bool ObjectReader::boolean(const std::string& key, bool def) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_boolean, "true or false");
  if (!v) {
    if (!present && valid_) (*obj_)[key] = def;
    return def;
  }
  return v->get<bool>();
}

const nlohmann::json* ObjectReader::peek(const std::string& key) const {
  if (!valid_ || !obj_) return nullptr;
  const auto it = obj_->find(key);
  return it == obj_->end() ? nullptr : &*it;
}

std::string ObjectReader::string(const std::string& key, const std::string& def) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_string, "a string");
  if (!v) {
    if (!present && valid_) (*obj_)[key] = def;
    return def;
  }
  return v->get<std::string>();
}

std::optional<std::string> ObjectReader::requiredString(const std::string& key) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_string, "a string");
  if (!present && valid_) issue(key, "missing required key (a string)");
  if (!v) return std::nullopt;
  return v->get<std::string>();
}

namespace {

std::string listOf(const std::vector<std::string>& allowed) {
  std::string s;
  for (const std::string& a : allowed) {
    if (!s.empty()) s += ", ";
    s += '"';
    s += a;
    s += '"';
  }
  return s;
}

}  // namespace

std::string ObjectReader::choice(const std::string& key, const std::string& def,
                                 const std::vector<std::string>& allowed) {
  const bool present = has(key);
  const std::string v = string(key, def);
  if (present && std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
    // a wrong type was already reported by string()
    if ((*obj_)[key].is_string()) {
      const std::string hint = closestKey(v, allowed);
      issue(key, "must be one of " + listOf(allowed) + ", got " + quote(v) +
                     (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
    }
    return def;
  }
  return v;
}

std::optional<std::string> ObjectReader::requiredChoice(const std::string& key,
                                                        const std::vector<std::string>& allowed) {
  auto v = requiredString(key);
  if (!v) return std::nullopt;
  if (std::find(allowed.begin(), allowed.end(), *v) == allowed.end()) {
    const std::string hint = closestKey(*v, allowed);
    issue(key, "must be one of " + listOf(allowed) + ", got " + quote(*v) +
                   (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
    return std::nullopt;
  }
  return v;
}

Eigen::VectorXd ObjectReader::vector(const std::string& key, const Eigen::VectorXd& def, Range each) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_array, "an array");
  const auto n = def.size();
  if (!v) {
    if (!present && valid_) (*obj_)[key] = std::vector<double>(def.data(), def.data() + n);
    return def;
  }
  if (static_cast<Eigen::Index>(v->size()) != n) {
    issue(key, "expected " + std::to_string(n) + " numbers, got " + std::to_string(v->size()));
    return def;
  }
  Eigen::VectorXd out = def;
  bool ok = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto x = checkedAt(pathOf(key) + "/" + std::to_string(i), (*v)[static_cast<size_t>(i)], each);
    if (x) out[i] = *x;
    else ok = false;
  }
  return ok ? out : def;
}

Vec3 ObjectReader::vec3(const std::string& key, const Vec3& def, Range each) {
  return vector(key, Eigen::VectorXd(def), each);
}

nlohmann::json* ObjectReader::array(const std::string& key) { return get(key, &nlohmann::json::is_array, "an array"); }

std::vector<double> ObjectReader::numbers(const std::string& key, const std::vector<double>& def, Range each,
                                          size_t min_len, size_t max_len) {
  const bool present = has(key);
  nlohmann::json* v = get(key, &nlohmann::json::is_array, "an array");
  if (!v) {
    if (!present && valid_) (*obj_)[key] = def;
    return def;
  }
  if (v->size() < min_len || v->size() > max_len) {
    issue(key, "expected " + std::to_string(min_len) + " to " + std::to_string(max_len) + " numbers, got " +
                   std::to_string(v->size()));
    return def;
  }
  std::vector<double> out;
  bool ok = true;
  for (size_t i = 0; i < v->size(); ++i) {
    const auto x = checkedAt(pathOf(key) + "/" + std::to_string(i), (*v)[i], each);
    if (x) out.push_back(*x);
    else ok = false;
  }
  return ok ? out : def;
}

std::vector<ObjectReader> ObjectReader::objects(const std::string& key) {
  std::vector<ObjectReader> out;
  nlohmann::json* v = get(key, &nlohmann::json::is_array, "an array");
  if (!v) return out;
  for (size_t i = 0; i < v->size(); ++i)
    out.push_back(ObjectReader(&(*v)[i], pathOf(key) + "/" + std::to_string(i), *issues_));
  return out;
}

ObjectReader ObjectReader::object(const std::string& key) {
  known_.push_back(key);
  // inside a non-object nothing more can be read or reported
  if (!valid_) return ObjectReader(nullptr, pathOf(key), *issues_);
  nlohmann::json& v = (*obj_)[key];  // inserts null when absent
  if (v.is_null()) v = nlohmann::json::object();  // null reads as "all defaults"
  return ObjectReader(&v, pathOf(key), *issues_);
}

ObjectReader::ObjectReader(nlohmann::json* obj, std::string path, IssueList& issues)
    : obj_(obj), path_(std::move(path)), issues_(&issues), valid_(obj && obj->is_object()) {
  if (obj && !valid_) issues_->add(path_, "expected an object, got " + jsonTypeName(*obj));
}

void ObjectReader::finish() {
  if (!valid_) return;
  for (auto it = obj_->begin(); it != obj_->end(); ++it) {
    if (std::find(known_.begin(), known_.end(), it.key()) != known_.end()) continue;
    // an object of a million unknown keys: the report lists 20, the rest
    // are only counted (and need no edit distances)
    if (issues_->full()) {
      issue(it.key(), "unknown key");
      continue;
    }
    const std::string hint = closestKey(it.key(), known_);
    issue(it.key(), "unknown key" + (hint.empty() ? std::string() : " (did you mean \"" + hint + "\"?)"));
  }
}

}  // namespace groundsim::scenario
