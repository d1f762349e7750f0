#include "scenario/json_limits.hpp"

#include <unordered_set>
#include <utility>
#include <vector>

#include "scenario/object_reader.hpp"

namespace groundsim::scenario {
namespace {

using json = nlohmann::json;

std::string tooDeep(const Budget& b) {
  return "nested deeper than " + std::to_string(b.max_depth) + " levels of objects and arrays " +
         b.flag("max-depth");
}

std::string tooMany(const Budget& b) {
  return "more than " + std::to_string(b.max_json_values) + " JSON values " + b.flag("max-json-values");
}

// nlohmann's what() starts with "[json.exception.parse_error.101] "
std::string reason(const std::string& what) {
  if (const auto p = what.find("] "); what.rfind("[json.exception", 0) == 0 && p != std::string::npos)
    return what.substr(p + 2);
  return what;
}

// A SAX handler: no tree, one frame per open object or array holding what
// the path and the duplicate check need. Returning false stops the parse.
class Scanner {
 public:
  Scanner(const Budget& b, IssueList& issues) : b_(b), issues_(issues) {}

  bool null() { return value(); }
  bool boolean(bool) { return value(); }
  bool number_integer(json::number_integer_t) { return value(); }
  bool number_unsigned(json::number_unsigned_t) { return value(); }
  bool number_float(json::number_float_t, const json::string_t&) { return value(); }
  bool string(json::string_t&) { return value(); }
  bool binary(json::binary_t&) { return value(); }
  bool start_object(std::size_t) { return open(true); }
  bool start_array(std::size_t) { return open(false); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(json::string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    if (!f.keys.insert(k).second)
      issues_.add(path(), "duplicate key " + quote(k) + " (JSON keeps only one of them: give each key once)");
    return true;
  }

  bool parse_error(std::size_t byte, const std::string&, const nlohmann::detail::exception& e) {
    // out_of_range.406: "number overflow parsing '1e999'", not representable,
    // so not validatable either
    if (e.id == 406) issues_.add("", "invalid JSON: " + reason(e.what()));
    else issues_.add("", "malformed JSON at byte " + std::to_string(byte) + ": " + reason(e.what()));
    return false;
  }

 private:
  struct Frame {
    bool object = false;
    std::size_t index = 0;  // arrays: of the next element
    std::string key;        // objects: the current key
    std::unordered_set<std::string> keys;
  };

  // JSON pointer of the value being read
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) p += "/" + (f.object ? pointerToken(f.key) : std::to_string(f.index));
    return p;
  }

  bool value() {
    if (++values_ > b_.max_json_values) {
      issues_.add(path(), tooMany(b_));
      return false;
    }
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    return true;
  }
  bool open(bool object) {
    if (frames_.size() >= static_cast<std::size_t>(b_.max_depth)) {
      issues_.add(path(), tooDeep(b_));
      return false;
    }
    if (++values_ > b_.max_json_values) {
      issues_.add(path(), tooMany(b_));
      return false;
    }
    frames_.push_back(Frame{object, 0, {}, {}});
    return true;
  }
  bool close() {
    frames_.pop_back();
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    return true;
  }

  const Budget& b_;
  IssueList& issues_;
  std::vector<Frame> frames_;
  std::size_t values_ = 0;
};

}  // namespace

void scanText(const std::string& text, const Budget& budget, IssueList& issues) {
  if (text.size() > budget.max_document_bytes) {
    issues.add("", "document of " + std::to_string(text.size()) + " bytes, at most " +
                       std::to_string(budget.max_document_bytes) + " " + budget.flag("max-document-bytes"));
    return;
  }
  Scanner scanner(budget, issues);
  json::sax_parse(text, &scanner);
}

void checkTree(const json& doc, const Budget& budget, IssueList& issues) {
  // (value, depth) pairs: an explicit stack instead of recursion
  std::vector<std::pair<const json*, int>> stack{{&doc, 0}};
  std::size_t values = 0;
  while (!stack.empty()) {
    const auto [v, depth] = stack.back();
    stack.pop_back();
    if (++values > budget.max_json_values) return issues.add("", tooMany(budget));
    if (!v->is_structured()) continue;
    if (depth >= budget.max_depth) return issues.add("", tooDeep(budget));
    for (const json& child : *v) stack.emplace_back(&child, depth + 1);
  }
}

}  // namespace groundsim::scenario
