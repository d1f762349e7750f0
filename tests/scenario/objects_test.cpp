// `objects` and `collisions`: every bad input names its path and reason;
// the model budget counts objects with mass exactly.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

nlohmann::json withObjects(const nlohmann::json& objects) {
  auto d = minimalDoc();
  d["vehicle"]["name"] = "vehicle";
  d["objects"] = objects;
  return d;
}

nlohmann::json cone(const std::string& name) {
  return {{"name", name}, {"shape", "cone"}, {"mass", 3}, {"position", {5, 0, 0}}};
}

TEST(Objects, EveryShapeIsAcceptedWithItsOwnKeys) {
  const auto d = withObjects({{{"name", "b"}, {"shape", "box"}, {"size", {1, 2, 3}}, {"rounding", 0.1}, {"position", {9, 0, 0}}},
                              {{"name", "s"}, {"shape", "sphere"}, {"radius", 0.3}, {"mass", 2}, {"position", {0, 9, 0}}},
                              {{"name", "c"}, {"shape", "cylinder"}, {"radius", 0.3}, {"height", 1}, {"position", {0, -9, 0}}},
                              {{"name", "p"}, {"shape", "capsule"}, {"radius", 0.2}, {"height", 1}, {"mass", 1}, {"position", {-9, 0, 0}}},
                              cone("k")});
  const Scenario s = parseScenario(d);
  ASSERT_EQ(s.objects.size(), 5u);
  const auto scene = buildScene(s);
  const Model& m = *scene.built.model;
  EXPECT_TRUE(m.collisions);
  EXPECT_EQ(m.objects.size(), 5u);
  // with mass: a body each, resting on the ground: lowest point at z = 0
  const SceneObject& k = m.objects[4];
  ASSERT_GE(k.body, 0);
  EXPECT_NEAR(bodyPos(scene.built.initial.y, k.body).z() + k.pos.z() - k.shape.half_height, 0.0, 1e-9);
  EXPECT_EQ(m.objects[0].body, -1);
}

TEST(Objects, BadObjectsNameTheirPathAndReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto issues = issuesOf(withObjects(
      {{{"name", "a"}, {"shape", "pyramid"}},
       {{"name", "b"}, {"shape", "box"}, {"radius", 1}},
       {{"shape", "sphere"}},
       {{"name", "vehicle"}, {"shape", "sphere"}},
       {{"name", "e"}, {"shape", "box"}, {"size", {1, -1, 1}}},
       {{"name", "f"}, {"shape", "box"}, {"size", {1, 1, 1}}, {"rounding", 0.9}},
       {{"name", "g"}, {"shape", "capsule"}, {"radius", 1}, {"height", 1}},
       {{"name", "h"}, {"shape", "sphere"}, {"mass", nan}},
       {{"name", "i"}, {"shape", "sphere"}, {"mass", -1}},
       {{"name", "j"}, {"shape", "sphere"}, {"position", {1, 2}}},
       {{"name", "a"}, {"shape", "sphere"}}}));
  EXPECT_TRUE(hasIssue(issues, "/objects/0/shape", "\"box\"")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/1/radius", "unknown")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/2/name", "missing")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/3/name", "already the name")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/4/size/1")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/5/rounding", "at most half")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/6/height", "at least twice the radius")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/7/mass")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/8/mass")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/9/position")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects/10/name", "already the name")) << listed(issues);
}

TEST(Objects, TooManyObjectsAreRefusedInOneLine) {
  nlohmann::json many = nlohmann::json::array();
  for (int i = 0; i < 1001; ++i) many.push_back({{"name", "o" + std::to_string(i)}, {"shape", "sphere"}});
  const auto issues = issuesOf(withObjects(many));
  ASSERT_EQ(issues.size(), 1u) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/objects", "1001 objects, at most 1000"));
  EXPECT_TRUE(hasIssue(issuesOf(withObjects({{"shape", "box"}, {"name", "x"}})), "/objects"));  // not an array of objects
  auto d = minimalDoc();
  d["objects"] = "walls";
  EXPECT_TRUE(hasIssue(issuesOf(d), "/objects", "array"));
}

TEST(Objects, BadCollisionKeysNameTheirPath) {
  auto d = minimalDoc();
  d["collisions"] = {{"frequency", -1}, {"damping_ratio", "high"}, {"enabled", 1}, {"stifness", 5}};
  const auto issues = issuesOf(d);
  EXPECT_TRUE(hasIssue(issues, "/collisions/frequency")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/collisions/damping_ratio", "number")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/collisions/enabled")) << listed(issues);
  EXPECT_TRUE(hasIssue(issues, "/collisions/stifness", "stiffness")) << listed(issues);  // the typo's hint
}

TEST(Objects, BudgetCountsObjectsWithMassExactly) {
  const Scenario s = parseScenario(withObjects({cone("k1"), cone("k2"),
                                                {{"name", "wall"}, {"shape", "box"}, {"size", {0.3, 9, 1}}, {"position", {0, 5, 0}}}}));
  const ModelSize e = estimateModelSize(s);
  const auto scene = buildScene(s);
  const Model& m = *scene.built.model;
  EXPECT_EQ(e.bodies, static_cast<long long>(m.bodies.size()));
  EXPECT_EQ(e.points, static_cast<long long>(m.points.size()));
  EXPECT_EQ(e.contact_points, static_cast<long long>(m.contact_points.size()));
  EXPECT_EQ(e.state, static_cast<long long>(m.stateSize()));
}

TEST(Objects, CollisionsOffLeaveTheModelWithoutContactBetweenBodies) {
  auto d = withObjects(nlohmann::json::array({cone("k")}));
  d["collisions"] = {{"enabled", false}};
  const auto scene = buildScene(parseScenario(d));
  EXPECT_FALSE(scene.built.model->collisions);
  // one vehicle alone has nothing to touch
  EXPECT_FALSE(buildScene(parseScenario(minimalDoc())).built.model->collisions);
}

}  // namespace
}  // namespace groundsim::scenario::test
