// The broad phase of contact between bodies (forces/body_contact.cpp):
// oriented boxes against sampled truth, cars in neighbouring lanes that are
// not candidates, and a melee of every kind of body in which no contact is
// ever found (by the narrow phase over all pairs) in a pair the broad phase
// dropped at the step's start.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "physics/forces/body_contact.hpp"
#include "physics/collision/obb.hpp"
#include "physics/forces/forces.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim {
namespace {

using nlohmann::json;

Mat3 randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// A box overlaps another when a point of one lies in the other: sampled on
// a grid of each box (corners, edges, faces and inside), which finds every
// overlap deeper than the grid's spacing.
bool sampledOverlap(const OrientedBox& a, const OrientedBox& b) {
  constexpr int n = 12;
  for (const auto& [p, q] : {std::pair(&a, &b), std::pair(&b, &a)})
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j)
        for (int k = 0; k <= n; ++k) {
          const Vec3 u = Vec3(i, j, k) * (2.0 / n) - Vec3::Ones();
          if (contains(*q, p->c + p->R * p->h.cwiseProduct(u), 0.0)) return true;
        }
  return false;
}

TEST(BroadPhase, OrientedBoxesSeparateOnlyWhenApart) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> size(0.1, 2.0), place(-3.0, 3.0);
  int overlapping = 0, apart = 0;
  for (int t = 0; t < 400; ++t) {
    OrientedBox a{Vec3::Zero(), randomRotation(rng), Vec3(size(rng), size(rng), size(rng))};
    OrientedBox b{Vec3(place(rng), place(rng), place(rng)), randomRotation(rng), Vec3(size(rng), size(rng), size(rng))};
    const bool sampled = sampledOverlap(a, b);
    // a point of one inside the other: the test must say they overlap
    if (sampled) {
      EXPECT_TRUE(overlap(a, b)) << "trial " << t;
    }
    // the test is symmetric
    EXPECT_EQ(overlap(a, b), overlap(b, a)) << "trial " << t;
    overlapping += sampled;
    apart += !overlap(a, b);
  }
  // both outcomes were exercised
  EXPECT_GT(overlapping, 50);
  EXPECT_GT(apart, 50);
  // two unit cubes 1 mm apart along x, one turned about x: apart
  const OrientedBox c{Vec3::Zero(), Mat3::Identity(), Vec3::Constant(0.5)};
  const OrientedBox d{Vec3(1.001, 0, 0), Eigen::AngleAxisd(0.3, Vec3::UnitX()).toRotationMatrix(), Vec3::Constant(0.5)};
  EXPECT_FALSE(overlap(c, d));
  // edge to edge, turned 45 degrees about z: the corner reaches sqrt(2)/2
  OrientedBox e{Vec3(0.5 + 0.5 * std::sqrt(2.0) - 0.01, 0, 0),
                      Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()).toRotationMatrix(), Vec3::Constant(0.5)};
  EXPECT_TRUE(overlap(c, e));
  e.c.x() += 0.02;
  EXPECT_FALSE(overlap(c, e));
}

json roadCar(const std::string& name, double x, double y, double yaw_deg, double speed) {
  return {{"name", name},
          {"kind", "road_car"},
          {"initial", {{"position", {x, y, 0.0}}, {"yaw_deg", yaw_deg}, {"speed", speed}}}};
}

struct SceneRun {
  scenario::Scene scene;
  std::unique_ptr<Simulator> sim;
};

SceneRun load(const json& doc) {
  SceneRun r;
  r.scene = scenario::buildScene(scenario::parseScenario(doc));
  r.sim = std::make_unique<Simulator>(r.scene.built.model, r.scene.built.initial);
  return r;
}

std::set<std::pair<int, int>> candidates(const Model& m, const Eigen::VectorXd& y, Workspace& ws) {
  ws.step_pairs = false;
  groupsMayTouch(m, y, m.opt.dt, ws);
  return {ws.pairs.begin(), ws.pairs.end()};
}

// Sedans side by side in lanes 3.5 m apart and nose to tail 12 m apart: the
// bounding spheres (2.9 m) of neighbours overlap, their boxes do not, so no
// pair is a candidate and no step takes contact substeps.
TEST(BroadPhase, CarsInNeighbouringLanesAreNotCandidates) {
  json cars = json::array();
  for (int i = 0; i < 4; ++i) cars.push_back(roadCar("c" + std::to_string(i), 12.0 * (i / 2), i % 2 ? 1.75 : -1.75, 0, 20));
  SceneRun r = load({{"name", "lanes"}, {"ground", {{"type", "plane"}}}, {"physics", {{"dt", 0.004}}}, {"vehicles", cars}});
  const Model& m = r.sim->model();
  ASSERT_TRUE(m.collisions);
  Workspace ws(m, false);
  for (int k = 0; k < 250; ++k) {
    ASSERT_TRUE(candidates(m, r.sim->state().y, ws).empty()) << "step " << k;
    ASSERT_TRUE(scenario::stepScene(r.scene, *r.sim, 1));
  }
  // the same cars 0.3 m apart side by side are candidates
  cars[1]["initial"]["position"] = {0.0, -1.75 + 1.8 + 0.3, 0.0};
  SceneRun close = load({{"name", "close"}, {"ground", {{"type", "plane"}}}, {"physics", {{"dt", 0.004}}}, {"vehicles", cars}});
  Workspace wc(close.sim->model(), false);
  EXPECT_EQ(candidates(close.sim->model(), close.sim->state().y, wc).count({0, 1}), 1u);
}

// A road car is one rigid body: its box holds its shapes and probes as
// they are, with no margin for parts that move against it (issue 33). Two
// sedans side by side with 0.4 m between their bodies at 10 m/s (each box
// padded by 2 x 0.04 m + 1 cm for the step) are no pair, so they cost what
// cars far apart cost; nose to tail 0.5 m apart neither.
TEST(BroadPhase, RigidCarsAFewDecimetresApartAreNotCandidates) {
  const json cars = {roadCar("a", 0, 0, 0, 10), roadCar("b", 0, 2.2, 0, 10), roadCar("c", -5.2, 0, 0, 10)};
  SceneRun r = load({{"name", "near"}, {"ground", {{"type", "plane"}}}, {"physics", {{"dt", 0.004}}}, {"vehicles", cars}});
  const Model& m = r.sim->model();
  ASSERT_TRUE(m.collisions);
  for (const CollisionGroup& g : m.groups) {
    EXPECT_TRUE(g.rigid) << g.name;
    EXPECT_NEAR(2.0 * g.box_h.y(), 1.16 * 1.55, 1e-9) << g.name;  // the body box's width: no margin
  }
  Workspace ws(m, false);
  for (int k = 0; k < 250; ++k) {
    ASSERT_TRUE(candidates(m, r.sim->state().y, ws).empty()) << "step " << k;
    ASSERT_TRUE(scenario::stepScene(r.scene, *r.sim, 1));
  }
  EXPECT_EQ(r.sim->forceEvaluations(), 250);  // no contact substeps
}

// After every step, the narrow phase over all pairs finds contact only in
// pairs the broad phase kept at the step's start, and the narrow phase
// over the probes the census listed at the step's start (the step's
// evaluations test only those) finds every contact it finds, bit for bit.
struct Melee {
  size_t met = 0;             // pairs that touched
  int touching_steps = 0;     // steps that ended with a contact
  double dropped = 0.0;       // fraction of pair-steps the broad phase dropped
  long listed = 0;            // census entries over the run
};
Melee checkMelee(const json& doc, int steps) {
  SceneRun r = load(doc);
  const Model& m = r.sim->model();
  EXPECT_TRUE(m.collisions);
  Workspace bp(m, false), all(m, false);
  const std::vector<WheelControl> controls(m.wheels.size());
  all.pairs.clear();
  for (int a = 0; a < static_cast<int>(m.groups.size()); ++a)
    for (int b = a + 1; b < static_cast<int>(m.groups.size()); ++b)
      if (m.groups[a].ref_body >= 0 || m.groups[b].ref_body >= 0) all.pairs.emplace_back(a, b);
  int touching_steps = 0;
  long dropped = 0;
  std::set<std::pair<int, int>> met;
  long listed = 0;
  for (int k = 0; k < steps; ++k) {
    const std::set<std::pair<int, int>> kept = candidates(m, r.sim->state().y, bp);
    bp.step_pairs = true;
    if (!kept.empty()) contactSubsteps(m, r.sim->state().y, bp, m.opt.dt);
    listed += static_cast<long>(bp.census.size());
    if (!scenario::stepScene(r.scene, *r.sim, 1)) {
      ADD_FAILURE() << r.sim->state().health_reason;
      return {};
    }
    computeKinematics(m, r.sim->state().y, controls, all);
    all.step_pairs = true;
    bodyContacts(m, false, all);
    if (!kept.empty()) {  // the step's pairs and census, at its end
      computeKinematics(m, r.sim->state().y, controls, bp);
      bodyContacts(m, false, bp);
      for (const PairContact& pc : all.pair_contacts) {
        const auto same = std::find_if(bp.pair_contacts.begin(), bp.pair_contacts.end(),
                                       [&](const PairContact& q) { return q.a == pc.a && q.b == pc.b; });
        if (same == bp.pair_contacts.end() || same->points != pc.points || same->normal != pc.normal) {
          ADD_FAILURE() << m.groups[pc.a].name << " and " << m.groups[pc.b].name << " at t " << r.sim->state().t
                        << " s: " << pc.points << " probes inside, " << pc.normal
                        << " N; the census of the step's start finds "
                        << (same == bp.pair_contacts.end() ? 0 : same->points) << " probes";
          return {};
        }
      }
      bp.step_census = false;
    }
    bp.step_pairs = false;
    touching_steps += !all.pair_contacts.empty();
    dropped += static_cast<long>(all.pairs.size() - kept.size());
    for (const PairContact& pc : all.pair_contacts) {
      met.insert({pc.a, pc.b});
      if (kept.count({pc.a, pc.b}) == 0) {
        ADD_FAILURE() << m.groups[pc.a].name << " and " << m.groups[pc.b].name << " touch at t " << r.sim->state().t
                      << " s (depth " << pc.depth << " m) but were not a candidate at the step's start";
        return {};
      }
    }
  }
  std::printf("%s: %zu pairs met, %d of %d steps in contact, %.1f%% of pair-steps dropped by the broad phase, "
              "%ld census entries\n",
              doc["name"].get<std::string>().c_str(), met.size(), touching_steps, steps,
              100.0 * dropped / (1.0 * steps * all.pairs.size()), listed);
  return {met.size(), touching_steps, dropped / (1.0 * steps * all.pairs.size()), listed};
}

// Road cars from three sides, the report's car, a lone wheel, a box and a
// cone with mass, and a static wall, at the fast preset's 2.5 ms.
TEST(BroadPhase, NoContactInAPairItDroppedInAMelee) {
  json doc = {
      {"name", "melee"},
      {"ground", {{"type", "plane"}}},
      {"contact", {{"friction", 0.8}}},
      {"preset", "fast"},
      {"vehicles",
       {roadCar("west", -14, 0, 0, 12), roadCar("east", 14, 1.0, 180, 12), roadCar("south", 0.5, -14, 90, 11),
        {{"name", "report"}, {"initial", {{"position", {3, 5, 0}}, {"yaw_deg", -100}, {"speed", 3}}}},
        {{"name", "wheel"}, {"kind", "wheel"}, {"initial", {{"position", {-1, -5, 0}}, {"yaw_deg", 80}, {"speed", 4}}}}}},
      {"objects",
       {{{"name", "crate"}, {"shape", "box"}, {"size", {1, 1, 1}}, {"mass", 200}, {"position", {2, -2.5, 0}}},
        {{"name", "cone"}, {"shape", "cone"}, {"mass", 3}, {"position", {-1.5, 1.5, 0}}},
        {{"name", "wall"}, {"shape", "box"}, {"size", {0.4, 12, 1}}, {"position", {0, 9, 0}}, {"yaw_deg", 80}}}}};
  const Melee r = checkMelee(doc, 1600);  // 4 s
  EXPECT_GE(r.met, 4u);
  EXPECT_GT(r.listed, 0);  // rigid pairs (road cars, the crate, the wall) were censused
  EXPECT_GT(r.touching_steps, 160);
  EXPECT_GT(r.dropped, 0.5);  // most pairs are far apart most of the time
}

// The deformable tyre (dt 0.2 ms) head-on into the report's car with rim
// points, a lone wheel crossing, a cone.
TEST(BroadPhase, NoContactInAPairItDroppedAmongSmallCars) {
  json doc = {
      {"name", "small"},
      {"ground", {{"type", "plane"}}},
      {"contact", {{"friction", 0.8}}},
      {"physics", {{"dt", 2e-4}}},
      {"vehicles",
       {{{"name", "report"}, {"initial", {{"position", {3, 0.5, 0}}, {"yaw_deg", 180}, {"speed", 3}}}},
        {{"name", "soft"}, {"wheel_model", "deformable"}, {"initial", {{"position", {-3, 0, 0}}, {"speed", 3}}}},
        {{"name", "wheel"}, {"kind", "wheel"}, {"initial", {{"position", {0, -4, 0}}, {"yaw_deg", 90}, {"speed", 4}}}}}},
      {"objects", {{{"name", "cone"}, {"shape", "cone"}, {"mass", 3}, {"position", {0.3, 3, 0}}}}}};
  const Melee r = checkMelee(doc, 10000);  // 2 s
  EXPECT_GE(r.met, 2u);
  EXPECT_GT(r.touching_steps, 500);
}

}  // namespace
}  // namespace groundsim
