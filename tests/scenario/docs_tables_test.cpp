// docs/scenario.md's key tables against the validator, so that the two
// cannot drift: every documented key is accepted and, where the table gives
// a default, the validator fills in that default (it writes every default
// back into Scenario::document); every key the validator fills in is
// documented. A table that disappears or is renamed fails here too.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

struct Row {
  std::vector<std::string> cells;
};
// heading (without the #s) -> rows of its first table
using Tables = std::map<std::string, std::vector<Row>>;

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::vector<std::string> splitRow(const std::string& line) {
  std::vector<std::string> cells;
  std::string cur;
  for (size_t i = 1; i < line.size(); ++i) {  // skip the leading '|'
    if (line[i] == '|') {
      cells.push_back(trim(cur));
      cur.clear();
    } else {
      cur += line[i];
    }
  }
  return cells;
}

Tables readTables() {
  std::ifstream in(std::string(GROUNDSIM_SOURCE_DIR) + "/docs/scenario.md");
  EXPECT_TRUE(in) << "docs/scenario.md not found";
  Tables t;
  std::string line, heading;
  bool in_table = false;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      heading = trim(line.substr(line.find_first_not_of('#')));
      in_table = false;
      continue;
    }
    if (line.rfind("|", 0) != 0) {
      in_table = false;
      continue;
    }
    if (line.rfind("|---", 0) == 0) continue;
    if (!in_table) {  // the header row: the first table under a heading counts
      in_table = true;
      if (t.count(heading)) heading += " (second table)";
      t[heading];
      continue;
    }
    t[heading].push_back({splitRow(line)});
  }
  return t;
}

// `a`, `b.c` in a cell
std::vector<std::string> keysIn(const std::string& cell) {
  std::vector<std::string> keys;
  static const std::regex tick("`([^`]+)`");
  for (auto it = std::sregex_iterator(cell.begin(), cell.end(), tick); it != std::sregex_iterator(); ++it)
    keys.push_back((*it)[1]);
  return keys;
}

const nlohmann::json* at(const nlohmann::json& obj, const std::string& dotted) {
  const nlohmann::json* v = &obj;
  std::stringstream ss(dotted);
  std::string seg;
  while (std::getline(ss, seg, '.')) {
    if (!v->is_object() || !v->contains(seg)) return nullptr;
    v = &(*v)[seg];
  }
  return v;
}

// The documented default: the cell up to " (" with backticks removed, as
// JSON. Numbers may be rounded in the docs (34.38 for 0.6 rad in degrees).
::testing::AssertionResult sameDefault(const std::string& cell, const nlohmann::json& actual) {
  std::string text = cell.substr(0, cell.find(" ("));
  text.erase(std::remove(text.begin(), text.end(), '`'), text.end());
  const nlohmann::json documented = nlohmann::json::parse(text, nullptr, false);
  if (documented.is_discarded()) return ::testing::AssertionFailure() << "default cell '" << cell << "' is not JSON";
  auto close = [](double a, double b) { return std::abs(a - b) <= 1e-3 * std::max(std::abs(a), std::abs(b)); };
  if (documented.is_number() && actual.is_number() ? close(documented.get<double>(), actual.get<double>())
      : documented.is_array() && actual.is_array() && documented.size() == actual.size()
          ? [&] {
              for (size_t i = 0; i < documented.size(); ++i)
                if (!close(documented[i].get<double>(), actual[i].get<double>())) return false;
              return true;
            }()
          : documented == actual)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "documented " << documented.dump() << ", validator fills in " << actual.dump();
}

// key | type | unit | default | ... (the ground rows are rearranged to match)
constexpr size_t kDefaultColumn = 3;

// Checks one table against the validated object `filled`; keys in `skip`
// are documented but not filled in (alternatives such as `vehicles`).
void checkTable(const Tables& tables, const std::string& heading, const nlohmann::json& filled,
                const std::vector<std::string>& skip = {}) {
  ASSERT_TRUE(tables.count(heading)) << "docs/scenario.md has no table under '" << heading << "'";
  std::set<std::string> documented;
  for (const Row& r : tables.at(heading)) {
    ASSERT_GT(r.cells.size(), kDefaultColumn) << heading;
    const std::string& def = r.cells[kDefaultColumn];
    for (const std::string& key : keysIn(r.cells[0])) {
      documented.insert(key);
      if (std::find(skip.begin(), skip.end(), key) != skip.end()) continue;
      const nlohmann::json* v = at(filled, key);
      if (def == "absent") {
        EXPECT_EQ(v, nullptr) << heading << ": " << key << " is documented as absent by default";
        continue;
      }
      ASSERT_NE(v, nullptr) << heading << ": documented key " << key << " is not filled in by the validator";
      if (def == "all defaults") EXPECT_TRUE(v->is_object()) << key;
      else if (def.find("**required**") == std::string::npos && !def.empty())
        EXPECT_TRUE(sameDefault(def, *v)) << heading << ": " << key;
    }
  }
  // every key the validator fills in is documented (nested objects by their dotted keys)
  for (auto it = filled.begin(); it != filled.end(); ++it) {
    if (documented.count(it.key())) continue;
    if (it->is_object() && !it->empty()) {
      for (auto jt = it->begin(); jt != it->end(); ++jt)
        EXPECT_TRUE(documented.count(it.key() + "." + jt.key()))
            << heading << ": the validator accepts " << it.key() << "." << jt.key() << ", the docs do not list it";
      continue;
    }
    ADD_FAILURE() << heading << ": the validator accepts " << it.key() << ", the docs do not list it";
  }
}

TEST(DocsTables, TopLevelPhysicsContactAndVehicleMatchTheValidator) {
  const Tables t = readTables();
  // from text: the name of a scenario given as text
  const Scenario s = parseScenario(std::string(R"({"ground": {"type": "plane"}, "vehicle": {}})"));
  const nlohmann::json& d = s.document;
  checkTable(t, "Top level", d, {"vehicles"});
  checkTable(t, "`physics`", d["physics"]);
  checkTable(t, "`contact`", d["contact"]);
  checkTable(t, "Vehicle object (`vehicle`, or each element of `vehicles`)", d["vehicle"]);
  checkTable(t, "`initial`", d["vehicle"]["initial"]);
  checkTable(t, "`control`", d["vehicle"]["control"]);
}

TEST(DocsTables, GroundTableMatchesTheValidatorForEveryType) {
  const Tables t = readTables();
  ASSERT_TRUE(t.count("Ground keys")) << "docs/scenario.md has no table under 'Ground keys'";
  // rows: `type` | `key` | unit | default | range
  std::map<std::string, std::vector<Row>> by_type;
  for (const Row& r : t.at("Ground keys")) {
    ASSERT_GE(r.cells.size(), 4u);
    const auto types = keysIn(r.cells[0]);
    ASSERT_EQ(types.size(), 1u) << r.cells[0];
    by_type[types[0]].push_back({{r.cells[1], r.cells[1], r.cells[2], r.cells[3]}});
  }
  // values for the required keys, so the rest can take defaults
  const std::map<std::string, nlohmann::json> required = {
      {"angle_deg", 10},     {"curvature", 0.1},    {"slope", 0.1},        {"amplitude", 0.1},
      {"wavelength_x", 5.0}, {"wavelength_y", 5.0}, {"expression", "z"}};
  for (const char* type : {"plane", "incline", "cosine", "parabola", "cone", "bumps", "expression"}) {
    SCOPED_TRACE(type);
    ASSERT_TRUE(by_type.count(type)) << "no rows for ground type " << type;
    auto d = minimalDoc();
    d["ground"] = {{"type", type}};
    for (const Row& r : by_type[type])
      for (const std::string& key : keysIn(r.cells[0]))
        if (r.cells[3].find("**required**") != std::string::npos) {
          ASSERT_TRUE(required.count(key)) << key;
          // and it really is required
          EXPECT_TRUE(hasIssue(issuesOf(d), "/ground/" + key, "missing required key"));
          d["ground"][key] = required.at(key);
        }
    nlohmann::json filled = parseScenario(d).document["ground"];
    filled.erase("type");
    Tables one{{std::string("ground ") + type, by_type[type]}};
    checkTable(one, std::string("ground ") + type, filled);
  }
}

TEST(DocsTables, TaskTablesMatchTheValidator) {
  const Tables t = readTables();
  // a road car named "car" (the documented default vehicle), so the
  // action's default is car_controls
  const Scenario s = parseScenario(nlohmann::json::parse(
      R"({"ground": {"type": "plane"}, "vehicle": {"kind": "road_car"}, "task": {"observation": ["speed"]}})"));
  const nlohmann::json& d = s.document["task"];
  checkTable(t, "`task`", d);
  checkTable(t, "`height_samples`", d["height_samples"]);
  checkTable(t, "`action`", d["action"]);
  checkTable(t, "`reward`", d["reward"]);
  checkTable(t, "`termination`", d["termination"]);
  checkTable(t, "`randomize`", d["randomize"]);
  // every feature the validator knows is documented, and no other
  ASSERT_TRUE(t.count("`task` (second table)"));
  std::set<std::string> documented;
  for (const Row& r : t.at("`task` (second table)"))
    for (const std::string& k : keysIn(r.cells.at(0))) documented.insert(k);
  const std::set<std::string> known(featureNames().begin(), featureNames().end());
  EXPECT_EQ(documented, known);
}

}  // namespace
}  // namespace groundsim::scenario::test
