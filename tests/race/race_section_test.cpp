// The scenario's `race` section: what it accepts, and hostile sections
// refused with the field named.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scenario/scenario.hpp"

namespace groundsim::scenario {
namespace {

using json = nlohmann::json;

json twoCars(json race) {
  json car = {{"kind", "road_car"}};
  json a = car, b = car;
  a["name"] = "a";
  b["name"] = "b";
  a["initial"] = {{"position", {0, 0, 0}}};
  b["initial"] = {{"position", {0, 10, 0}}};
  return {{"ground", {{"type", "plane"}}}, {"vehicles", {a, b}}, {"race", std::move(race)}};
}

json goodRace() {
  return {{"laps", 2},
          {"gates", {{{"left", {0, 5}}, {"right", {0, -5}}}, {{"center", {50, 0}}, {"width", 10}, {"heading_deg", 90}}}},
          {"grid", {{{"position", {-10, 2}}, {"heading_deg", 0}}, {{"position", {-10, -3}}}}},
          {"track", {{"centerline", {{-20, 0}, {60, 0}, {60, 40}}}, {"half_width", 8}}}};
}

std::vector<std::string> issues(const json& d) {
  try {
    parseScenario(d);
  } catch (const ScenarioError& e) {
    std::vector<std::string> out;
    for (const Issue& i : e.issues()) out.push_back(i.str());
    return out;
  }
  return {};
}

bool has(const std::vector<std::string>& v, const std::string& prefix) {
  for (const auto& s : v)
    if (s.rfind(prefix, 0) == 0) return true;
  return false;
}

std::string all(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + "\n";
  return s;
}

TEST(Section, ReadsGatesGridAndTrack) {
  const Scenario s = parseScenario(twoCars(goodRace()));
  ASSERT_TRUE(s.race.has_value());
  EXPECT_EQ(s.race->laps, 2);
  ASSERT_EQ(s.race->gates.size(), 2u);
  // centre + width + heading: heading 90 deg (forward +y), left post at -x
  EXPECT_NEAR(s.race->gates[1].left[0], 45.0, 1e-12);
  EXPECT_NEAR(s.race->gates[1].left[1], 0.0, 1e-12);
  EXPECT_NEAR(s.race->gates[1].right[0], 55.0, 1e-12);
  // the grid places the vehicles
  EXPECT_EQ(s.vehicles[0].placement.position.x(), -10.0);
  EXPECT_EQ(s.vehicles[1].placement.position.y(), -3.0);
  EXPECT_EQ(s.race->centerline.size(), 3u);
  EXPECT_EQ(s.race->half_width, 8.0);
  EXPECT_EQ(s.race->countdown, RaceSpec{}.countdown);
  // the session reads it back from the document it keeps
  const auto again = readRaceSection(s.document);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->gates.size(), 2u);
  EXPECT_FALSE(readRaceSection(json{{"ground", {{"type", "plane"}}}}).has_value());
}

TEST(Section, HostileRacesNameTheField) {
  struct Case {
    const char* what;
    json race;
    const char* field;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Case> cases;
  auto with = [&](const char* what, const char* key, json value, const char* field) {
    json r = goodRace();
    r[key] = std::move(value);
    cases.push_back({what, r, field});
  };
  auto gate1 = [&](const char* what, json gate, const char* field) {
    json r = goodRace();
    r["gates"][1] = std::move(gate);
    cases.push_back({what, r, field});
  };
  with("laps 0", "laps", 0, "/race/laps: ");
  with("laps huge", "laps", 1e9, "/race/laps: ");
  with("laps text", "laps", "3", "/race/laps: ");
  with("countdown NaN", "countdown", nan, "/race/countdown: ");
  with("countdown negative", "countdown", -1, "/race/countdown: ");
  with("gates not an array", "gates", 5, "/race/gates: ");
  with("one gate", "gates", json::array({goodRace()["gates"][0]}), "/race/gates: ");
  with("grid not an array", "grid", "front", "/race/grid: ");
  with("unknown key", "lapz", 3, "/race/lapz: unknown key");
  with("more bots than cars", "bots", 3, "/race/bots: 3 bots for 2 vehicles");
  with("negative bots", "bots", -1, "/race/bots: ");
  with("bots NaN", "bots", nan, "/race/bots: ");
  gate1("zero width (posts)", {{"left", {3, 3}}, {"right", {3, 3}}}, "/race/gates/1/right: ");
  gate1("zero width (centred)", {{"center", {3, 3}}, {"width", 0}, {"heading_deg", 0}}, "/race/gates/1/width: ");
  gate1("NaN post", {{"left", {nan, 0}}, {"right", {3, 3}}}, "/race/gates/1/left/0: ");
  gate1("infinite post", {{"left", {0, 0}}, {"right", {inf, 3}}}, "/race/gates/1/right/0: ");
  gate1("post of 3 numbers", {{"left", {0, 0, 0}}, {"right", {3, 3}}}, "/race/gates/1/left: ");
  gate1("missing right", {{"left", {0, 0}}}, "/race/gates/1/right: ");
  gate1("both forms", {{"left", {0, 0}}, {"right", {0, 5}}, {"width", 5}}, "/race/gates/1/left: ");
  gate1("NaN heading", {{"center", {3, 3}}, {"width", 5}, {"heading_deg", nan}}, "/race/gates/1/heading_deg: ");
  gate1("a gate that is a number", 7, "/race/gates/1: ");
  gate1("far away", {{"left", {1e7, 0}}, {"right", {1e7, 5}}}, "/race/gates/1/left/0: ");
  {
    json r = goodRace();
    r["grid"][1]["position"] = {nan, 0};
    cases.push_back({"NaN grid slot", r, "/race/grid/1/position/0: "});
  }
  {
    json r = goodRace();
    r["grid"] = json::array({r["grid"][0]});
    cases.push_back({"fewer slots than cars", r, "/race/grid: "});
  }
  {
    json r = goodRace();
    r["track"]["centerline"][1] = {nan, 1};
    cases.push_back({"NaN centre line point", r, "/race/track/centerline/1/0: "});
  }
  {
    json r = goodRace();
    r["track"]["centerline"][2] = "x";
    cases.push_back({"centre line point not a pair", r, "/race/track/centerline/2: "});
  }
  {
    json r = goodRace();
    r["track"].erase("half_width");
    cases.push_back({"no half width", r, "/race/track/half_width: "});
  }
  {
    json r = goodRace();
    r["circuit"] = false;
    cases.push_back({"a stage of two laps", r, "/race/laps: "});
  }
  for (const Case& c : cases) {
    const auto got = issues(twoCars(c.race));
    EXPECT_TRUE(has(got, c.field)) << c.what << ": expected " << c.field << ", got\n" << all(got);
  }
  EXPECT_TRUE(has(issues(twoCars(5)), "/race: expected an object")) << all(issues(twoCars(5)));
}

TEST(Section, AMillionGatesAreRefusedInOneLine) {
  json r = goodRace();
  const json gate = r["gates"][0];
  // 1e6 gates (numbers here: a million objects would take the test's memory,
  // not the validator's): past the document's value limit, refused before any gate is read
  json gates = json::array();
  for (int i = 0; i < 1000000; ++i) gates.push_back(i);
  r["gates"] = std::move(gates);
  const auto got = issues(twoCars(std::move(r)));
  ASSERT_FALSE(got.empty());
  EXPECT_LE(got.size(), kMaxListedIssues + 1);
  EXPECT_TRUE(has(got, "/: ") || has(got, "/race/gates")) << all(got);
  // within the document's value limit, past the section's: one line naming the field
  json r1 = goodRace();
  json small = json::array();
  for (int i = 0; i < 200000; ++i) small.push_back(i);
  r1["gates"] = std::move(small);
  const auto got1 = issues(twoCars(std::move(r1)));
  ASSERT_EQ(got1.size(), 1u) << all(got1);
  EXPECT_TRUE(has(got1, "/race/gates: 200000 gates, at most 1000")) << all(got1);

  // within the document's limits, past the section's
  json r2 = goodRace();
  json many = json::array();
  for (int i = 0; i < kMaxRaceGates + 1; ++i) many.push_back(gate);
  r2["gates"] = std::move(many);
  const auto got2 = issues(twoCars(std::move(r2)));
  EXPECT_TRUE(has(got2, "/race/gates: 1001 gates, at most 1000")) << all(got2);
}

TEST(Section, ShippedTracksValidate) {
  for (const char* f : {"/race/circuit.json", "/race/rally_stage.json"}) {
    const Scenario s = loadScenarioFile(std::string(GROUNDSIM_CONFIGS) + f);
    ASSERT_TRUE(s.race.has_value()) << f;
    EXPECT_GE(s.race->gates.size(), 4u) << f;
  }
}

}  // namespace
}  // namespace groundsim::scenario
