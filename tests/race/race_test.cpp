// The race layer against closed forms: a point driven at constant speed
// through gates crosses each at distance / speed, lap times are the track's
// length over the speed, to well within a step.
#include <gtest/gtest.h>

#include <cmath>

#include "race/race.hpp"

namespace groundsim::race {
namespace {

constexpr double kPi = 3.14159265358979323846;

scenario::RaceGate radialGate(double angle, double r_in, double r_out) {
  // counter-clockwise travel: forward is +angle; seen that way the outer post is on the right
  scenario::RaceGate g;
  g.left = {r_in * std::cos(angle), r_in * std::sin(angle)};
  g.right = {r_out * std::cos(angle), r_out * std::sin(angle)};
  return g;
}

struct Drive {
  std::vector<RaceEvent> events;
  void add(const std::vector<RaceEvent>& e) { events.insert(events.end(), e.begin(), e.end()); }
  std::vector<RaceEvent> of(EventKind k) const {
    std::vector<RaceEvent> out;
    for (const auto& e : events)
      if (e.kind == k) out.push_back(e);
    return out;
  }
};

TEST(Crossing, FindsTheFractionAndTheDirection) {
  double s = -1;
  // gate from (0, 1) to (0, -1): forward is +x
  EXPECT_EQ(crossing({-1, 0}, {3, 0}, {0, 1}, {0, -1}, &s), 1);
  EXPECT_DOUBLE_EQ(s, 0.25);
  EXPECT_EQ(crossing({3, 0}, {-1, 0}, {0, 1}, {0, -1}, &s), -1);
  EXPECT_DOUBLE_EQ(s, 0.75);
  EXPECT_EQ(crossing({-1, 2}, {3, 2}, {0, 1}, {0, -1}, &s), 0);   // beside the posts
  EXPECT_EQ(crossing({-1, 0}, {-0.5, 0}, {0, 1}, {0, -1}, &s), 0);  // short of the line
  EXPECT_EQ(crossing({0, 0}, {1, 0}, {0, 1}, {0, -1}, &s), 1);    // on the line at the start: this step
  EXPECT_EQ(crossing({-1, 0}, {0, 0}, {0, 1}, {0, -1}, &s), 0);   // at the end: the next step
}

// A point circling at radius R with speed v, counter-clockwise from angle
// -0.1 rad, gates at 0, 2 pi / 3, 4 pi / 3: the crossings are at
// (angle + 0.1) R / v, laps 2 pi R / v.
TEST(Race, CircularTrackLapsAndSplitsMatchTheClosedForm) {
  const double R = 50.0, v = 20.0, dt = 0.004, a0 = -0.1;
  scenario::RaceSpec spec;
  spec.laps = 3;
  spec.countdown = 0.0;
  for (int g = 0; g < 3; ++g) spec.gates.push_back(radialGate(g * 2 * kPi / 3, R - 5, R + 5));
  Race race(spec, 1);
  Drive d;
  auto at = [&](double t) {
    const double a = a0 + v * t / R;
    return Vec2{R * std::cos(a), R * std::sin(a)};
  };
  const double lap = 2 * kPi * R / v;
  for (long i = 0; i < static_cast<long>((3 * lap + 2) / dt); ++i)
    d.add(race.step(i * dt, (i + 1) * dt, {at(i * dt)}, {at((i + 1) * dt)}));

  const auto start = d.of(EventKind::Start), gates = d.of(EventKind::Gate), laps = d.of(EventKind::Lap);
  ASSERT_EQ(start.size(), 1u);
  const double t_start = 0.1 * R / v;
  EXPECT_NEAR(start[0].t, t_start, 1e-6 * dt);
  ASSERT_EQ(gates.size(), 6u);  // gates 1 and 2 of each lap
  for (std::size_t i = 0; i < gates.size(); ++i) {
    EXPECT_EQ(gates[i].gate, static_cast<int>(i % 2) + 1);
    EXPECT_NEAR(gates[i].time, (i % 2 + 1) * lap / 3, 1e-6 * dt) << i;
  }
  ASSERT_EQ(laps.size(), 3u);
  for (std::size_t i = 0; i < laps.size(); ++i) {
    EXPECT_NEAR(laps[i].time, lap, 1e-6 * dt) << i;
    EXPECT_NEAR(laps[i].t, t_start + (i + 1) * lap, 1e-6 * dt) << i;
    EXPECT_EQ(laps[i].lap, static_cast<int>(i) + 1);
  }
  const auto fin = d.of(EventKind::Finish);
  ASSERT_EQ(fin.size(), 1u);
  EXPECT_NEAR(fin[0].time, t_start + 3 * lap, 1e-6 * dt);
  EXPECT_EQ(fin[0].position, 1);
  EXPECT_TRUE(race.standing(0).finished);
  EXPECT_NEAR(race.standing(0).best_lap, lap, 1e-6 * dt);
  EXPECT_TRUE(race.over());
}

// A straight stage: gates every 100 m across the x axis, a car at 25 m/s
// whose start is not on a step boundary: stage time = 300 m / 25 m/s, each
// split 100 m / 25 m/s, independent of the step.
TEST(Race, StraightStageTimesAreDistanceOverSpeed) {
  for (double dt : {0.004, 0.01, 0.0333}) {
    scenario::RaceSpec spec;
    spec.circuit = false;
    spec.countdown = 1.0;  // held until t = 1
    for (int g = 0; g < 4; ++g) spec.gates.push_back({{100.0 * g, 6.0}, {100.0 * g, -6.0}});
    Race race(spec, 1);
    Drive d;
    const double v = 25.0, x0 = -7.3;
    auto x = [&](double t) { return t < 1.0 ? x0 : x0 + v * (t - 1.0); };
    for (long i = 0; i < static_cast<long>(16.0 / dt); ++i)
      d.add(race.step(i * dt, (i + 1) * dt, {Vec2{x(i * dt), 0.3}}, {Vec2{x((i + 1) * dt), 0.3}}));
    ASSERT_EQ(d.of(EventKind::Go).size(), 1u);
    EXPECT_EQ(d.of(EventKind::Go)[0].t, 1.0);
    const auto start = d.of(EventKind::Start);
    ASSERT_EQ(start.size(), 1u);
    EXPECT_NEAR(start[0].t, 1.0 + 7.3 / v, 1e-9);
    const auto gates = d.of(EventKind::Gate);
    ASSERT_EQ(gates.size(), 3u);
    for (int g = 0; g < 3; ++g) EXPECT_NEAR(gates[static_cast<std::size_t>(g)].time, 100.0 * (g + 1) / v, 1e-9);
    const auto laps = d.of(EventKind::Lap);
    ASSERT_EQ(laps.size(), 1u) << "dt " << dt;
    EXPECT_NEAR(laps[0].time, 300.0 / v, 1e-9);
    ASSERT_EQ(d.of(EventKind::Finish).size(), 1u);
    EXPECT_NEAR(d.of(EventKind::Finish)[0].time, (300.0 + 7.3) / v, 1e-9);
  }
}

TEST(Race, NothingCountsBeforeGoAndGatesOnlyInOrder) {
  scenario::RaceSpec spec;
  spec.countdown = 2.0;
  spec.circuit = false;
  spec.gates = {{{0, 5}, {0, -5}}, {{10, 5}, {10, -5}}, {{20, 5}, {20, -5}}};
  Race race(spec, 1);
  Drive d;
  // before go: crossing gate 0 does not start the car
  d.add(race.step(0.0, 1.0, {Vec2{-1, 0}}, {Vec2{1, 0}}));
  EXPECT_TRUE(d.events.empty());
  EXPECT_FALSE(race.standing(0).started);
  d.add(race.step(1.0, 2.0, {Vec2{1, 0}}, {Vec2{-1, 0}}));
  // after go: gate 2 skipped around the side does not count, gate 1 must come first
  d.add(race.step(2.0, 3.0, {Vec2{-1, 0}}, {Vec2{1, 0}}));
  d.add(race.step(3.0, 4.0, {Vec2{1, 0}}, {Vec2{5, 8}}));
  d.add(race.step(4.0, 5.0, {Vec2{5, 8}}, {Vec2{25, 0}}));  // passes x = 10 and 20 at y > 5 ... then inside
  EXPECT_EQ(d.of(EventKind::Start).size(), 1u);
  EXPECT_EQ(d.of(EventKind::Gate).size(), 0u);
  EXPECT_EQ(race.standing(0).next_gate, 1);
}

TEST(Race, WrongWayAfterItsTimeAndBackWhenTurned) {
  scenario::RaceSpec spec;
  spec.countdown = 0.0;
  spec.wrong_way_time = 1.0;
  spec.gates = {{{0, 5}, {0, -5}}, {{100, 5}, {100, -5}}, {{100, 50}, {90, 50}}};
  Race race(spec, 1);
  Drive d;
  const double dt = 0.01;
  double x = -5;
  double t = 0;
  auto run = [&](double v, double seconds) {
    for (long i = 0; i < static_cast<long>(seconds / dt + 0.5); ++i, t += dt) {
      const double x1 = x + v * dt;
      d.add(race.step(t, t + dt, {Vec2{x, 0}}, {Vec2{x1, 0}}));
      x = x1;
    }
  };
  run(10.0, 2.0);  // through the start line, towards gate 1
  EXPECT_TRUE(d.of(EventKind::WrongWay).empty());
  run(-10.0, 0.9);  // backwards, less than wrong_way_time
  EXPECT_TRUE(d.of(EventKind::WrongWay).empty());
  run(-10.0, 0.2);
  auto ww = d.of(EventKind::WrongWay);
  ASSERT_EQ(ww.size(), 1u);
  EXPECT_TRUE(ww[0].on);
  EXPECT_NEAR(ww[0].t, 2.0 + 1.0, 1.5 * dt);
  EXPECT_TRUE(race.standing(0).wrong_way);
  run(0.5, 1.0);  // crawling: no verdict either way
  EXPECT_EQ(d.of(EventKind::WrongWay).size(), 1u);
  run(10.0, 0.1);
  ww = d.of(EventKind::WrongWay);
  ASSERT_EQ(ww.size(), 2u);
  EXPECT_FALSE(ww[1].on);
  EXPECT_FALSE(race.standing(0).wrong_way);
}

TEST(Race, OffTrackBeyondTheHalfWidthAndBack) {
  scenario::RaceSpec spec;
  spec.countdown = 0.0;
  spec.circuit = false;
  spec.gates = {{{0, 5}, {0, -5}}, {{100, 5}, {100, -5}}};
  spec.centerline = {{-10, 0}, {50, 0}, {110, 0}};
  spec.half_width = 5.0;
  Race race(spec, 1);
  Drive d;
  d.add(race.step(0, 1, {Vec2{1, 0}}, {Vec2{2, 4.9}}));
  EXPECT_TRUE(d.of(EventKind::OffTrack).empty());
  d.add(race.step(1, 2, {Vec2{2, 4.9}}, {Vec2{3, 5.1}}));
  ASSERT_EQ(d.of(EventKind::OffTrack).size(), 1u);
  EXPECT_TRUE(d.of(EventKind::OffTrack)[0].on);
  d.add(race.step(2, 3, {Vec2{3, 5.1}}, {Vec2{4, 4.9}}));  // inside the hysteresis band: still off
  EXPECT_EQ(d.of(EventKind::OffTrack).size(), 1u);
  d.add(race.step(3, 4, {Vec2{4, 4.9}}, {Vec2{5, 1.0}}));
  ASSERT_EQ(d.of(EventKind::OffTrack).size(), 2u);
  EXPECT_FALSE(d.of(EventKind::OffTrack)[1].on);
}

TEST(Race, LeaderboardAndRespawnPose) {
  scenario::RaceSpec spec;
  spec.countdown = 0.0;
  spec.laps = 1;
  spec.gates = {{{0, 5}, {0, -5}}, {{50, 5}, {50, -5}}, {{50, 105}, {50, 95}}};
  spec.grid = {{{-5, 2}, 0.0}, {{-5, -2}, 0.0}};
  Race race(spec, 2);
  // neither started: the grid
  auto p = race.respawnPose(1);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->gate, -1);
  EXPECT_EQ(p->position[1], -2.0);
  race.step(0, 1, {Vec2{-5, 2}, Vec2{-5, -2}}, {Vec2{60, 2}, Vec2{5, -2}});  // car 0 past gate 1, car 1 past gate 0
  const auto board = race.leaderboard();
  EXPECT_EQ(board[0].car, 0);
  EXPECT_EQ(board[1].car, 1);
  p = race.respawnPose(0);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->gate, 1);
  EXPECT_NEAR(p->position[0], 52.0, 1e-12);  // 2 m past the gate's centre, facing +x
  EXPECT_NEAR(p->yaw, 0.0, 1e-12);
  const auto ev = race.respawned(0, *p, 1.0);
  ASSERT_FALSE(ev.empty());
  EXPECT_EQ(ev.back().kind, EventKind::Respawn);
  EXPECT_TRUE(race.isProtected(0, 1.0 + spec.respawn_protection - 0.01));
  EXPECT_FALSE(race.isProtected(0, 1.0 + spec.respawn_protection));
  // reasons are one line of JSON after "race: "
  const std::string r = Race::reason(ev.back(), {"a", "b"});
  EXPECT_EQ(r.rfind("race: {", 0), 0u) << r;
  EXPECT_NE(r.find("\"type\":\"respawn\""), std::string::npos) << r;
  EXPECT_NE(race.standingsReason(1.0, {"a", "b"}).find("\"cars\":[{"), std::string::npos);
}

}  // namespace
}  // namespace groundsim::race
