// Command-line overrides: "vehicle.wheel_radius=0.5" sets one value of the
// raw document before validation, so an override is checked exactly like
// the same value written in the file.
#include <algorithm>
#include <cctype>

#include "scenario/json_limits.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::scenario {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw ScenarioError({Issue{path, message}});
}

bool isIndex(const std::string& s) {
  return !s.empty() && s.size() < 10 && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

}  // namespace

void applyOverride(nlohmann::json& doc, const std::string& assignment, const Budget& budget) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    fail("", "override " + quote(assignment) + ": expected key.path=value");
  const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
  const std::string name = "override " + quote(key);

  // the value: JSON when it parses ("0.5", "[1,0]", "true", "\"x\""), else the
  // text itself, so `--set ground.type=cone` needs no quotes. Valid JSON is
  // held to the document limits before its tree is built.
  nlohmann::json value;
  if (nlohmann::json::accept(text)) {
    IssueList limits;
    scanText(text, budget, limits);
    if (!limits.empty()) fail("", name + ": " + limits.items().front().message);
    value = nlohmann::json::parse(text);
  } else {
    value = text;
  }

  if (!doc.is_object()) fail("", name + ": the document is not an object");
  nlohmann::json* at = &doc;
  std::string path;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    const std::string seg = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (seg.empty()) fail("", name + ": empty key segment");
    path += '/';
    path += pointerToken(seg);
    const bool last = dot == std::string::npos;
    nlohmann::json* next = nullptr;
    if (at->is_array()) {
      if (!isIndex(seg)) fail(path, name + ": expected an array index, got " + quote(seg));
      const size_t i = std::stoul(seg);
      if (i >= at->size())
        fail(path, name + ": index " + seg + " is past the end (" + std::to_string(at->size()) +
                       " elements)");
      next = &(*at)[i];
    } else if (at->is_object()) {
      // missing intermediate objects are created: physics.dt=1e-4 works
      // without a physics section in the file
      next = &(*at)[seg];
      if (!last && next->is_null()) *next = nlohmann::json::object();
    } else {
      fail(path, name + ": cannot set a key inside a value of type " + jsonTypeName(*at));
    }
    if (last) {
      *next = std::move(value);
      return;
    }
    at = next;
    start = dot + 1;
  }
}

}  // namespace groundsim::scenario
