// The bridge's race parts: what a browser joining mid-race is sent, and the
// race in the joined layout.
#include <gtest/gtest.h>

#include "bridge/browser_message.hpp"
#include "bridge/race_relay.hpp"

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

}  // namespace
}  // namespace groundsim::web
