// The traffic rules (server/drivers/traffic.*): a bot on a straight behind
// a car stopped on its line stops behind it, the gap kept (min_gap, 2 m,
// bumper to bumper), then goes round it, with no contact, where the same
// driver without the rules runs into it; two bots side by side on a grid merge onto one line
// without touching, one letting the other in first.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "drivers/lap_run.hpp"
#include "drivers/traffic.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::drivers {
namespace {

const char* kStraight = R"({"physics": {"dt": 0.004}, "contact": {"friction": 1.0}, "ground": {"type": "plane"},
  "vehicles": [{"name": "bot", "kind": "road_car", "initial": {"position": [0, 0, 0]}},
               {"name": "stopped", "kind": "road_car", "initial": {"position": [60, 0, 0]}}],
  "race": {"circuit": false, "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0},
                                       {"center": [400, 0], "width": 14, "heading_deg": 0}],
           "track": {"centerline": [[-10, 0], [200, 0], [400, 0]], "half_width": 7}}})";

struct Behind {
  double stopped_gap = -1.0;  // m  bumper to bumper when it first stood behind the car (-1: never)
  int touches = 0;            // steps with the two cars in contact
  double ahead = 0.0;         // m  how far past the stopped car it is at the end (x)
};

// A race scene with its simulator, the race's line and the classical
// driver's speed profile on it.
struct Scene {
  explicit Scene(const char* doc)
      : s(scenario::parseScenario(std::string(doc))), scene(scenario::buildScene(s)), m(*scene.built.model),
        sim(scene.built.model, scene.built.initial), line(racingLine(*s.race), false, 1.0),
        profile(line, CarLimits{}, frictionAlong(m, line)) {}
  scenario::Scenario s;
  scenario::Scene scene;
  const Model& m;
  Simulator sim;
  TrackLine line;
  SpeedProfile profile;
};

Behind driveBehind(bool rules) {
  Scene sc(kStraight);
  const Model& m = sc.m;
  Simulator& sim = sc.sim;
  std::unique_ptr<Driver> d = std::make_unique<ClassicalBot>(sc.line, sc.profile, m, 0);
  const TrafficRules tr;
  if (rules) d = std::make_unique<TrafficAware>(std::move(d), m.road_cars[0].body, std::vector<int>{m.road_cars[1].body}, 0, tr);
  CarControls stopped;
  stopped.brake = 1.0;
  sim.setCarControls(1, stopped);
  Behind r;
  for (int k = 0; k < 7500; ++k) {  // 30 s
    if (k % 5 == 0) {
      sim.setCarControls(0, toControls(d->drive(m, sim.state())));
    }
    EXPECT_TRUE(sim.step());
    for (const Hit& h : sim.hits())
      if (m.groups[h.a].vehicle >= 0 && m.groups[h.b].vehicle >= 0) ++r.touches;
    const Vec3 a = bodyPos(sim.state().y, m.road_cars[0].body), b = bodyPos(sim.state().y, m.road_cars[1].body);
    if (r.stopped_gap < 0.0 && b.x() > a.x() && Vec3(bodyVel(sim.state().y, m.road_cars[0].body)).norm() < 0.05 &&
        sim.state().t > 1.0)
      r.stopped_gap = (b - a).norm() - tr.length;
    r.ahead = a.x() - b.x();
  }
  return r;
}

TEST(Traffic, ABotStopsBehindACarOnItsLineThenGoesRoundItWhereWithoutTheRulesItHitsIt) {
  const Behind with = driveBehind(true), without = driveBehind(false);
  std::printf("with the rules: stood %.2f m behind it, then %.1f m past it, %d steps touching; without: %d steps "
              "touching\n", with.stopped_gap, with.ahead, with.touches, without.touches);
  EXPECT_GT(without.touches, 0) << "the scene does not test anything: the bare driver never reaches the car";
  EXPECT_EQ(with.touches, 0);
  // it stood behind it, about min_gap (2 m) bumper to bumper: more than half of it, not far behind
  EXPECT_GT(with.stopped_gap, 0.5 * TrafficRules{}.min_gap);
  EXPECT_LT(with.stopped_gap, TrafficRules{}.min_gap + 4.0);
  // and, the car staying there, went round it
  EXPECT_GT(with.ahead, TrafficRules{}.length);
}

// A car under respawn protection has the way (TrafficAware::setProtected):
// a car standing 3.5 m beside the bot's line (outside its corridor of
// 2.2 m, inside its lane of 5.5 m) is one the bot drives by at speed; put
// there by a respawn, the bot stops behind it, at least min_gap bumper to
// bumper, and never goes round it while the protection lasts (the car is
// about to drive off). Once the protection ends the bot drives on by it,
// the two never touching.
TEST(Traffic, ABotGivesWayToARespawnedCarUntilItsProtectionEnds) {
  const char* doc = R"({"physics": {"dt": 0.004}, "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "bot", "kind": "road_car", "initial": {"position": [0, 0, 0]}},
                 {"name": "respawned", "kind": "road_car", "initial": {"position": [60, 3.5, 0]}}],
    "race": {"circuit": false, "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0},
                                         {"center": [400, 0], "width": 14, "heading_deg": 0}],
             "track": {"centerline": [[-10, 0], [200, 0], [400, 0]], "half_width": 7}}})";
  const TrafficRules tr;
  struct Run {
    double closest = 1e300;  // m  the bot's centre behind the other's while protected (x), least
    double ahead = 0.0;      // m  past it at the end
    int touches = 0;
  };
  auto run = [&](double protected_for) {
    Scene sc(doc);
    const Model& m = sc.m;
    Simulator& sim = sc.sim;
    TrafficAware d(std::make_unique<ClassicalBot>(sc.line, sc.profile, m, 0), m.road_cars[0].body,
                   std::vector<int>{m.road_cars[1].body}, 0, tr);
    CarControls stopped;
    stopped.brake = 1.0;
    sim.setCarControls(1, stopped);
    Run r;
    for (int k = 0; k < 5000; ++k) {  // 20 s
      const double t = sim.state().t;
      if (k % 5 == 0) {
        d.setProtected(0, t < protected_for);
        sim.setCarControls(0, toControls(d.drive(m, sim.state())));
      }
      EXPECT_TRUE(sim.step());
      for (const Hit& h : sim.hits())
        if (m.groups[h.a].vehicle >= 0 && m.groups[h.b].vehicle >= 0) ++r.touches;
      const Vec3 a = bodyPos(sim.state().y, m.road_cars[0].body), b = bodyPos(sim.state().y, m.road_cars[1].body);
      if (t < protected_for) r.closest = std::min(r.closest, b.x() - a.x());
      r.ahead = a.x() - b.x();
    }
    return r;
  };
  const Run open = run(0.0), given = run(12.0);
  std::printf("unprotected: %.1f m past it; protected for 12 s: at least %.2f m behind it (centres) meanwhile, then "
              "%.1f m past it; %d and %d steps touching\n",
              open.ahead, given.closest, given.ahead, open.touches, given.touches);
  EXPECT_GT(open.ahead, 100.0) << "the scene does not test anything: the bot stops for a car beside its line";
  // while protected: behind it, a car length and at least half min_gap between the bumpers
  EXPECT_GT(given.closest, tr.length + 0.5 * tr.min_gap);
  // then on by it
  EXPECT_GT(given.ahead, tr.length);
  EXPECT_EQ(open.touches, 0);
  EXPECT_EQ(given.touches, 0);
}

TEST(Traffic, TwoBotsSideBySideMergeOntoOneLineWithoutTouching) {
  const char* doc = R"({"physics": {"dt": 0.004}, "contact": {"friction": 1.0}, "ground": {"type": "plane"},
    "vehicles": [{"name": "a", "kind": "road_car"}, {"name": "b", "kind": "road_car"}],
    "race": {"circuit": false, "countdown": 0,
             "gates": [{"center": [10, 0], "width": 14, "heading_deg": 0}, {"center": [400, 0], "width": 14, "heading_deg": 0}],
             "grid": [{"position": [0, 2.5]}, {"position": [0, -2.5]}],
             "track": {"centerline": [[-10, 0], [200, 0], [400, 0]], "half_width": 7}}})";
  Scene sc(doc);
  const Model& m = sc.m;
  Simulator& sim = sc.sim;
  const int body[2] = {m.road_cars[0].body, m.road_cars[1].body};
  TrafficAware a(std::make_unique<ClassicalBot>(sc.line, sc.profile, m, 0), body[0], std::vector<int>{body[1]}, 0);
  TrafficAware b(std::make_unique<ClassicalBot>(sc.line, sc.profile, m, 1), body[1], std::vector<int>{body[0]}, 1);
  int touches = 0;
  for (int k = 0; k < 3000; ++k) {  // 12 s: both on the line, one behind the other
    if (k % 5 == 0) {
      TrafficAware* d[2] = {&a, &b};
      for (int c = 0; c < 2; ++c) {
        sim.setCarControls(c, toControls(d[c]->drive(m, sim.state())));
      }
    }
    ASSERT_TRUE(sim.step());
    for (const Hit& h : sim.hits())
      if (m.groups[h.a].vehicle >= 0 && m.groups[h.b].vehicle >= 0) ++touches;
  }
  const Vec3 pa = bodyPos(sim.state().y, body[0]), pb = bodyPos(sim.state().y, body[1]);
  std::printf("after 12 s: a at (%.1f, %.2f), b at (%.1f, %.2f), %d steps touching\n", pa.x(), pa.y(), pb.x(), pb.y(),
              touches);
  EXPECT_EQ(touches, 0);
  EXPECT_LT(std::abs(pa.y()), 1.0);  // both on the line
  EXPECT_LT(std::abs(pb.y()), 1.0);
  EXPECT_GT(pa.x() - pb.x(), TrafficRules{}.length) << "the first in the order goes first, the other behind";
}

}  // namespace
}  // namespace groundsim::drivers
