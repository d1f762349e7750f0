// Track-following tasks (docs/scenario.md "Tasks", docs/drivers.md) against
// closed forms: on a circular track of radius R the line's curvature is
// 1/R and its point d ahead lies at (R sin(d/R), R (1 - cos(d/R))) from a
// car on it heading along it; on a straight stage the progress reward is
// the distance driven along it, the finish ends the episode with the lap
// reward, and a car beyond the edge pays for it. Starts drawn along the
// track land on the line with the line's heading.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "experiments/env.hpp"
#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

constexpr double kR = 50.0;   // m  the circle's radius
constexpr int kPoints = 400;  // the polyline's sagitta: R (1 - cos(pi / 400)) = 1.5 mm

// A counter-clockwise circle of radius kR about the origin, starting at (0, -kR) heading +x.
nlohmann::json circleRace() {
  nlohmann::json line = nlohmann::json::array();
  for (int i = 0; i < kPoints; ++i) {
    const double a = -std::numbers::pi / 2 + 2 * std::numbers::pi * i / kPoints;
    line.push_back({kR * std::cos(a), kR * std::sin(a)});
  }
  return {{"laps", 2},
          {"gates", {{{"left", {0.0, -kR + 6}}, {"right", {0.0, -kR - 6}}},
                     {{"left", {-kR + 6, 0.0}}, {"right", {-kR - 6, 0.0}}}}},
          {"track", {{"centerline", line}, {"half_width", 6.0}}}};
}

// A straight stage along +x: centre line y = 0 from x = 0, the finish gate at x = 60.
nlohmann::json straightStage() {
  return {{"circuit", false},
          {"gates", {{{"left", {0.0, 6.0}}, {"right", {0.0, -6.0}}}, {{"left", {60.0, 6.0}}, {"right", {60.0, -6.0}}}}},
          {"track", {{"centerline", {{0.0, 0.0}, {30.0, 0.0}, {200.0, 0.0}}}, {"half_width", 4.0}}}};
}

nlohmann::json onTrack(nlohmann::json race, nlohmann::json task, nlohmann::json initial) {
  nlohmann::json doc = roadCarDoc(plane(), std::move(task), std::move(initial));
  doc["race"] = std::move(race);
  return doc;
}

TEST(TrackTask, FeaturesOnACircleAreItsCurvatureAndItsArcAhead) {
  const double offset = 2.0;  // m, to the left: inside the circle
  nlohmann::json task = {{"observation", {"position", "track_pose", "track_ahead", "track_curvature", "next_gate"}},
                         {"track", {{"ahead", {5.0, 20.0, 40.0}}}}};
  Batch b(onTrack(circleRace(), task, {{"position", {0.0, -kR + offset, 0.0}}, {"yaw_deg", 0.0}}), 1);
  b.reset();
  EXPECT_NEAR(b.o("track_pose.offset"), offset, 2e-3);
  EXPECT_NEAR(b.o("track_pose.sin"), 0.0, 1e-3);
  EXPECT_NEAR(b.o("track_pose.cos"), 1.0, 1e-6);
  const double ds[3] = {5.0, 20.0, 40.0};
  // the line is resampled into chords of ds = 1 m, each turned by up to
  // ds / 2R from the circle's tangent: a car `offset` off the line finds its
  // foot on a chord up to offset ds / 2R = 0.02 m from the circle's
  const double kFoot = offset * 1.0 / (2 * kR) + 0.005;
  // the body centre where the scene put it (a road car's centre of mass sits
  // a little off its placement's point): its foot on the circle is at angle a0
  const double cx = b.o("position.x"), cy = b.o("position.y");
  const double a0 = std::atan2(cy, cx);
  ASSERT_NEAR(a0, -std::numbers::pi / 2, 1e-3);
  for (int k = 0; k < 3; ++k) {
    const std::string i = std::to_string(k);
    // the line's point at arc length d from the car's foot, seen from the car (heading +x)
    const double a = a0 + ds[k] / kR;
    const double x = kR * std::cos(a) - cx, y = kR * std::sin(a) - cy;
    EXPECT_NEAR(b.o("track_ahead." + i + ".x"), x, kFoot) << ds[k];
    EXPECT_NEAR(b.o("track_ahead." + i + ".y"), y, kFoot) << ds[k];
    EXPECT_NEAR(b.o("track_curvature." + i), 1.0 / kR, 0.01 / kR) << ds[k];
  }
  // the next gate: the second, a quarter of the circle on, at (-R, 0)
  EXPECT_NEAR(b.o("next_gate.x"), -kR - cx, 1e-4);
  EXPECT_NEAR(b.o("next_gate.y"), -cy, 1e-4);
}

TEST(TrackTask, ProgressIsTheDistanceDrivenAlongTheLineAndTheFinishEndsTheEpisode) {
  nlohmann::json task = {{"observation", {"position", "track_pose"}},
                         {"reward", {{"track_progress", 1.0}, {"lap", 100.0}}},
                         {"termination", {{"laps", 1}}},
                         {"time_limit", 10.0},
                         {"control_period", 5}};
  Batch b(onTrack(straightStage(), task, {{"position", {40.0, 0.5, 0.0}}, {"yaw_deg", 0.0}, {"speed", 10.0}}), 1);
  b.reset();
  b.setAll({0.3f, 0.0f, 0.0f});
  double x0 = b.o("position.x"), sum = 0.0;
  bool finished = false;
  for (int k = 0; k < 200 && !finished; ++k) {
    const double before = b.o("position.x");
    b.step();
    const double x = b.o("position.x");
    finished = b.term[0] != 0;
    // on a straight line along x the gain is the change of x, to rounding
    // (positions are float32 observations: 4e-6 m at 60 m)
    const double lap = finished ? 100.0 : 0.0;
    EXPECT_NEAR(b.rew[0] - lap, x - before, 2e-5) << "action " << k;
    sum += b.rew[0] - lap;
    if (finished) {
      EXPECT_GE(x, 59.0) << "the stage ends within a metre of its finish gate (x = 60)";
      EXPECT_LT(x, 59.0 + 10.0 * 5 * 0.004 * 2) << "and not later than the action that reached it";
    } else {
      EXPECT_LT(x, 59.0);
    }
  }
  EXPECT_TRUE(finished);
  EXPECT_NEAR(sum, b.o("position.x") - x0, 1e-4);
}

TEST(TrackTask, BeyondTheEdgeIsChargedAndFartherEndsTheEpisode) {
  nlohmann::json task = {{"observation", {"track_pose"}},
                         {"reward", {{"off_track", 1.0}}},
                         {"termination", {{"off_track", 1.5}}}};
  // the stage's half width is 4 m: at 5 m the car is 1 m beyond the edge, at 6 m 2 m
  Batch in(onTrack(straightStage(), task, {{"position", {20.0, 3.0, 0.0}}}), 1);
  Batch over(onTrack(straightStage(), task, {{"position", {20.0, 5.0, 0.0}}}), 1);
  Batch out(onTrack(straightStage(), task, {{"position", {20.0, -6.0, 0.0}}}), 1);
  for (Batch* b : {&in, &over, &out}) {
    b->reset();
    b->step();
  }
  EXPECT_EQ(in.rew[0], 0.0);
  EXPECT_EQ(in.term[0], 0);
  EXPECT_EQ(over.rew[0], -1.0);
  EXPECT_EQ(over.term[0], 0);
  EXPECT_EQ(out.rew[0], -1.0);
  EXPECT_EQ(out.term[0], 1);
}

TEST(TrackTask, StartsDrawnAlongTheTrackLandOnTheLineHeadingAlongIt) {
  nlohmann::json task = {{"observation", {"position", "heading", "track_pose"}},
                         {"randomize", {{"track_s", {0.0, 2 * std::numbers::pi * kR}}, {"y", {-1.0, 1.0}}}}};
  Batch b(onTrack(circleRace(), task, {{"position", {0.0, -kR, 0.0}}}), 8);
  b.reset(3);
  const Layout& l = b.layout();
  ASSERT_EQ(l.drawn.back(), "track_s");
  std::vector<double> drawn(static_cast<size_t>(8 * l.drawn.size()));
  b.env->drawn(drawn.data());
  double spread = 0.0;
  for (int e = 0; e < 8; ++e) {
    const double* d = drawn.data() + e * l.drawn.size();
    const double s = d[l.drawn.size() - 1], y = d[kDrawnY];
    // the drawn arc length and offset to the left (inside): radius R - y at angle -pi/2 + s/R
    const double a = -std::numbers::pi / 2 + s / kR;
    EXPECT_NEAR(b.o("position.x", e), (kR - y) * std::cos(a), 0.01) << e;
    EXPECT_NEAR(b.o("position.y", e), (kR - y) * std::sin(a), 0.01) << e;
    EXPECT_NEAR(b.o("track_pose.offset", e), y, 0.01) << e;
    EXPECT_NEAR(b.o("track_pose.sin", e), 0.0, 2e-3) << e;
    EXPECT_NEAR(b.o("heading.cos", e), std::cos(a + std::numbers::pi / 2), 2e-3) << e;
    spread = std::max(spread, s);
  }
  EXPECT_GT(spread, kR) << "the starts spread round the circle";
}

TEST(TrackTask, ATaskReadingATrackNeedsOne) {
  nlohmann::json task = {{"observation", {"track_pose"}}};
  try {
    Batch b(roadCarDoc(plane(), task), 1);
    FAIL() << "a track feature without a race was accepted";
  } catch (const scenario::ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("/task"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("race"), std::string::npos) << e.what();
  }
  // a width is needed to charge leaving the track: gates alone give a line, no width
  nlohmann::json race = straightStage();
  race.erase("track");
  nlohmann::json charged = {{"observation", {"track_pose"}}, {"reward", {{"off_track", 1.0}}}};
  try {
    Batch b(onTrack(race, charged, {{"position", {10.0, 0.0, 0.0}}}), 1);
    FAIL() << "off_track without a width was accepted";
  } catch (const scenario::ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("/task/reward/off_track"), std::string::npos) << e.what();
  }
}

TEST(TrackTask, SnapshotsCarryTheProgressAlongTheTrack) {
  nlohmann::json task = {{"observation", {"track_pose", "track_ahead"}},
                         {"reward", {{"track_progress", 1.0}, {"lap", 10.0}}},
                         {"control_period", 5},
                         {"randomize", {{"track_s", {0.0, 300.0}}, {"speed", {5.0, 10.0}}}}};
  const nlohmann::json doc = onTrack(circleRace(), task, {{"position", {0.0, -kR, 0.0}}});
  Batch a(doc, 1), b(doc, 1);
  a.reset(11);
  a.setAll({0.4f, 0.0f, 0.15f});
  b.setAll({0.4f, 0.0f, 0.15f});
  for (int k = 0; k < 20; ++k) a.step();
  const std::string snap = a.env->snapshot(0);
  std::vector<double> original, restored;
  for (int k = 0; k < 30; ++k) {
    a.step();
    original.push_back(a.rew[0]);
  }
  b.reset(5);
  b.env->restore(0, snap, b.obs.data());
  for (int k = 0; k < 30; ++k) {
    b.step();
    restored.push_back(b.rew[0]);
  }
  EXPECT_EQ(original, restored);
  EXPECT_EQ(a.env->info(0).episode_return, b.env->info(0).episode_return);
}

}  // namespace
}  // namespace groundsim::experiments::test
