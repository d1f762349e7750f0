// The bridge's race parts: what a browser joining mid-race is sent, and the
// race in the joined layout.
#include <gtest/gtest.h>

#include <cmath>

#include "bridge/browser_message.hpp"
#include "bridge/race_relay.hpp"
#include "bridge/shipped_scenarios.hpp"

namespace groundsim::web {
namespace {

std::shared_ptr<const std::string> msg(const std::string& s) { return std::make_shared<const std::string>(s); }

TEST(RaceRelay, KeepsTheLastLayoutAndStandings) {
  RaceRelay r;
  EXPECT_TRUE(r.catchUp().empty());
  r.note("hit: a and b at (0, 0, 0) m", msg("hit"));
  r.note("race: {\"t\":1,\"type\":\"lap\",\"car\":0}", msg("lap"));
  EXPECT_TRUE(r.catchUp().empty());
  r.note("race: {\"gates\":[],\"type\":\"race\"}", msg("layout1"));
  r.note("race: {\"type\":\"standings\",\"cars\":[]}", msg("standings1"));
  r.note("race: {\"type\":\"standings\",\"cars\":[1]}", msg("standings2"));
  auto c = r.catchUp();
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(*c[0], "layout1");
  EXPECT_EQ(*c[1], "standings2");
  // a reset announces the race again: the old standings go
  r.note("race: {\"type\":\"race\"}", msg("layout2"));
  c = r.catchUp();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(*c[0], "layout2");
  // not JSON, or no type: not a race event
  EXPECT_EQ(RaceRelay::type("race: {broken"), "");
  EXPECT_EQ(RaceRelay::type("race: {\"name\":\"\\\"type\\\":\\\"race\\\"\"}"), "");
  EXPECT_EQ(RaceRelay::type("racing: {\"type\":\"race\"}"), "");
}

TEST(RaceRelay, LayoutHoldsGatesAndCentreLine) {
  scenario::RaceSpec spec;
  spec.laps = 3;
  spec.gates = {{{0, 5}, {0, -5}}, {{50, 5}, {50, -5}}};
  spec.centerline = {{-10, 0}, {60, 0}};
  spec.half_width = 7;
  const auto j = raceLayout(spec);
  EXPECT_EQ(j["type"], "race");
  EXPECT_EQ(j["laps"], 3);
  EXPECT_EQ(j["gates"][1][0], 50.0);
  EXPECT_EQ(j["gates"][1][3], -5.0);
  EXPECT_EQ(j["centerline"].size(), 2u);
  EXPECT_EQ(j["half_width"], 7.0);
  EXPECT_EQ(j["go"], spec.countdown);
}

TEST(RaceRelay, RespawnIsABrowserOp) {
  const ParsedMessage m = parseBrowserMessage(R"({"op":"respawn"})");
  ASSERT_TRUE(m.message.has_value()) << m.error.field << ": " << m.error.reason;
  ASSERT_TRUE(std::holds_alternative<SessionOpMsg>(*m.message));
  EXPECT_EQ(std::get<SessionOpMsg>(*m.message).op, "respawn");
  EXPECT_FALSE(parseBrowserMessage(R"({"op":"respawn","vehicle":3})").message.has_value());  // its own car only
}

// H = z - h(x, y), h = 0.1 x + 0.002 y^2: a slope and a valley across it
class SlopedValley : public Ground {
 public:
  static double h(double x, double y) { return 0.1 * x + 0.002 * y * y; }
  double eval(const Vec3& p, Vec3* grad) const override {
    if (grad) *grad = Vec3(-0.1, -0.004 * p.y(), 1.0);
    return p.z() - h(p.x(), p.y());
  }
  std::string describe() const override { return "sloped valley"; }
};

// The ribbon's stations every metre or less along the centre line, unit
// normals to the left, and at each offset the ground's height there.
TEST(RaceRelay, TrackRibbonFollowsTheGround) {
  SlopedValley g;
  scenario::RaceSpec spec;
  spec.circuit = true;
  spec.centerline = {{0, 0}, {100, 0}, {100, 50}, {0, 50}};
  spec.half_width = 6.0;
  const auto j = trackRibbon(g, spec, 0.8);
  ASSERT_TRUE(j.is_object());
  const auto& xy = j["xy"];
  ASSERT_EQ(xy.size(), 300u);  // 300 m of closed line, every 1 m, the last station the first
  const auto& off = j["offsets"];
  EXPECT_EQ(off.front(), -6.0);
  EXPECT_EQ(off.back(), 6.0);
  for (size_t k = 1; k < off.size(); ++k) EXPECT_LE(off[k].get<double>() - off[k - 1].get<double>(), 1.5 + 1e-12);
  double worst = 0;
  for (size_t k = 0; k < xy.size(); ++k) {
    const double x = xy[k][0], y = xy[k][1], nx = j["normal"][k][0], ny = j["normal"][k][1];
    EXPECT_NEAR(std::hypot(nx, ny), 1.0, 1e-4);
    const size_t n = (k + 1) % xy.size();
    EXPECT_LE(std::hypot(xy[n][0].get<double>() - x, xy[n][1].get<double>() - y), 1.0 + 1e-3);
    for (size_t o = 0; o < off.size(); ++o) {
      const double at = off[o].get<double>();
      worst = std::max(worst, std::abs(j["z"][k][o].get<double>() - SlopedValley::h(x + at * nx, y + at * ny)));
    }
    EXPECT_EQ(j["mu"][k], 0.8);  // no patches: the scene's
  }
  EXPECT_LT(worst, 2e-3);  // millimetres, and the station's position to 1 mm
  // on the first straight (heading +x) the left normal is +y
  EXPECT_NEAR(j["normal"][50][1].get<double>(), 1.0, 1e-9);
  // a stage longer than 1.5 km: 1,500 steps, its last station at its end
  spec.circuit = false;
  spec.centerline = {{0, 0}, {2040, 0}};
  const auto s = trackRibbon(g, spec, 0.8);
  ASSERT_EQ(s["xy"].size(), 1501u);
  EXPECT_NEAR(s["step"].get<double>(), 1.36, 1e-9);
  EXPECT_NEAR(s["xy"][1500][0].get<double>(), 2040.0, 1e-3);
  // no centre line or no width: none
  spec.half_width = 0;
  EXPECT_TRUE(trackRibbon(g, spec, 0.8).is_null());
}

// A lobby card's data: the circuit's ground over its track, the track,
// its walls and kerbs, its car.
TEST(ShippedScenarios, PreviewOfTheCircuit) {
  const auto p = scenarioPreview(GROUNDSIM_CONFIG_DIR, "race/circuit.json");
  const auto& grid = p["grid"];
  EXPECT_EQ(grid["n"], 48);
  const double x0 = grid["x0"], y0 = grid["y0"], side = 47 * grid["step"].get<double>();
  // the track (x within 90 + 9, y within 30 + 9) and 12 m around it
  EXPECT_LE(x0, -111.0 + 1e-9);
  EXPECT_GE(x0 + side, 111.0 - grid["step"].get<double>());
  EXPECT_LE(y0, -51.0);
  EXPECT_GE(y0 + side, 51.0);
  EXPECT_EQ(p["track"]["centerline"].size(), 64u);
  EXPECT_EQ(p["track"]["half_width"], 9.0);
  EXPECT_EQ(p["track"]["closed"], true);
  EXPECT_EQ(p["objects"].size(), 38u);
  ASSERT_EQ(p["cars"].size(), 1u);
  EXPECT_EQ(p["cars"][0][0], -8.0);
  EXPECT_EQ(p["cars"][0][1], -27.5);
  // asphalt (mu 1.0 or so) somewhere on the grid: its friction patches
  bool asphalt = false;
  for (const auto& m : grid["mu"]) asphalt = asphalt || (m.is_number() && m.get<double>() >= 0.8);
  EXPECT_TRUE(asphalt);
}

}  // namespace
}  // namespace groundsim::web
