// "preset" on a road car: the settings are the ones the sweep of the sedan's
// manoeuvres chose (the "Road-car presets" table of docs/accuracy.md, written
// by bench/accuracy/tradeoff), and each keeps its bound on full braking from
// 100 km/h: against a converged reference (RK4 at 0.125 ms, the sweep's) and
// against the closed form v^2 / (2 mu g).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "scenario/presets.hpp"
#include "scenario/scenario.hpp"
#include "sedan.hpp"

namespace groundsim::test {
namespace {

using nlohmann::json;

double bound(const std::string& preset) { return preset == "accurate" ? 1e-3 : preset == "balanced" ? 1e-2 : 5e-2; }

struct DocRow {
  std::string integrator;
  double dt = 0;
};

// The rows "| `name` | bound | integrator | dt | ..." after the heading.
std::map<std::string, DocRow> docTable() {
  std::ifstream in(std::string(GROUNDSIM_SOURCE_DIR) + "/docs/accuracy.md");
  std::map<std::string, DocRow> rows;
  std::string line;
  bool in_section = false;
  while (std::getline(in, line)) {
    if (line.rfind("### ", 0) == 0) in_section = line == "### Road-car presets";
    if (!in_section || line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    for (std::string c; std::getline(ss, c, '|');) {
      const auto a = c.find_first_not_of(" `"), b = c.find_last_not_of(" `");
      cells.push_back(a == std::string::npos ? "" : c.substr(a, b - a + 1));
    }
    if (cells.size() >= 4) rows[cells[0]] = {cells[2], std::strtod(cells[3].c_str(), nullptr)};
  }
  return rows;
}

json braking(const std::string& preset) {
  json doc = scenario::loadScenarioDocument(std::string(GROUNDSIM_CONFIGS) + "/sedan.json");
  doc["vehicle"]["initial"]["speed"] = 100.0 / 3.6;
  doc["vehicle"]["controls"] = json::array({{{"t", 0}, {"brake", 1.0}}});
  if (!preset.empty()) {
    doc["preset"] = preset;
    scenario::applyPreset(doc, /*force=*/true);
  }
  return doc;
}

// Stopping distance over 4 s (the car stands from about 2.9 s).
double stop(const json& doc, Options* opt = nullptr) {
  const scenario::Scene scene = scenario::buildScene(scenario::parseScenario(doc));
  Simulator sim(scene.built.model, scene.built.initial);
  if (opt) *opt = sim.model().opt;
  const int body = sim.model().road_cars.at(0).body;
  const Vec3 p0 = bodyPos(sim.state().y, body);
  const long long n = std::llround(4.0 / sim.model().opt.dt);
  EXPECT_TRUE(scenario::stepScene(scene, sim, n));
  // standing: what still moves (~1 cm/s) is the body settling back from its dive
  EXPECT_LT(bodyVel(sim.state().y, body).norm(), 0.05);
  return (bodyPos(sim.state().y, body) - p0).norm();
}

class RoadPreset : public ::testing::TestWithParam<std::string> {};

TEST_P(RoadPreset, SettingsAreTheOnesDocsAccuracyGives) {
  const auto rows = docTable();
  ASSERT_TRUE(rows.count(GetParam())) << "docs/accuracy.md has no road-car preset row for " << GetParam();
  const DocRow& d = rows.at(GetParam());
  const json s = scenario::roadCarPresetSettings(GetParam());
  EXPECT_EQ(s["physics"]["integrator"], d.integrator);
  EXPECT_DOUBLE_EQ(s["physics"]["dt"].get<double>(), d.dt);
  EXPECT_EQ(s["physics"]["substeps"], 1);
  // and what a road-car scenario with the preset is built with
  const scenario::Scenario sc = scenario::parseScenario(braking(GetParam()));
  EXPECT_NO_THROW((void)scenario::buildScene(sc));
  EXPECT_EQ(integratorName(sc.options.integrator), d.integrator);
  EXPECT_DOUBLE_EQ(sc.options.dt, d.dt);
}

TEST_P(RoadPreset, BrakingFrom100KmhStaysWithinItsBound) {
  const double b = bound(GetParam());
  Options opt;
  const double d = stop(braking(GetParam()), &opt);
  json ref = braking("");
  ref["physics"] = {{"integrator", "rk4"}, {"dt", 1.25e-4}};
  ref["contact"]["friction_model"] = "regularized";  // RK4 is refused with stick-slip; the tyres do not use it
  const double d_ref = stop(ref);
  EXPECT_NEAR(d, d_ref, b * d_ref) << GetParam() << ": " << integratorName(opt.integrator) << " dt " << opt.dt;
  // closed form (mu 1, g 9.81): the ideal ABS holds the tyres at their peak
  // slip, so the stop is v^2/(2 mu g) less drag (38.92 m) plus the time the
  // load takes to move forward; 1% covers that, below 1% the reference does
  const double v = 100.0 / 3.6, closed = v * v / (2 * 1.0 * kG);
  EXPECT_NEAR(d, closed, std::max(b, 1e-2) * closed);
}

TEST(RoadPresets, LeaveTheReportCarsTableAloneAndRefuseNoRoadCarKey) {
  // a road car takes none of the report car's wheel keys
  json doc = braking("balanced");
  EXPECT_FALSE(doc["vehicle"].contains("wheel_model"));
  EXPECT_FALSE(doc["vehicle"].contains("bearing_stiffness"));
  // a report car keeps its own preset's physics
  json car = {{"preset", "balanced"}, {"ground", {{"type", "plane"}}}, {"vehicle", {{"name", "car"}}}};
  scenario::applyPreset(car, true);
  EXPECT_EQ(car["physics"], scenario::presetSettings("balanced")["physics"]);
  EXPECT_EQ(car["vehicle"]["wheel_model"], "circle");
}

INSTANTIATE_TEST_SUITE_P(All, RoadPreset, ::testing::Values("fast", "balanced", "accurate"));

}  // namespace
}  // namespace groundsim::test
