// The validated document is complete: every default is written in, and the
// defaults are the physics structs' own.
#include <gtest/gtest.h>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

TEST(Defaults, DocumentIsFilledWithThePhysicsDefaults) {
  const Scenario s = parseScenario(minimalDoc());
  const nlohmann::json& d = s.document;
  const Options opt;
  const CarParams car;
  const CarPlacement at;
  EXPECT_EQ(d["duration"], s.duration);
  EXPECT_EQ(d["output_rate"], s.output_rate);
  EXPECT_EQ(d["physics"]["dt"], opt.dt);
  EXPECT_EQ(d["physics"]["integrator"], "semi_implicit_euler");
  EXPECT_EQ(d["physics"]["substeps"], opt.substeps);
  EXPECT_EQ(d["physics"]["gravity"][2], opt.gravity.z());
  EXPECT_EQ(d["physics"]["limits"]["max_speed"], opt.limits.max_speed);
  EXPECT_EQ(d["contact"]["stiffness"], opt.contact.stiffness);
  EXPECT_EQ(d["contact"]["friction"], opt.contact.friction);
  EXPECT_EQ(d["contact"]["friction_model"], "stick_slip");
  EXPECT_EQ(d["vehicle"]["name"], "car");
  EXPECT_EQ(d["vehicle"]["rim_points"], car.rim_points);
  EXPECT_EQ(d["vehicle"]["wheel_radius"], car.wheel_radius);
  EXPECT_EQ(d["vehicle"]["body_mass"], car.body_mass);
  EXPECT_EQ(d["vehicle"]["wheel_model"], "rim_points");
  EXPECT_EQ(d["vehicle"]["coupling"], "rim_springs");
  EXPECT_EQ(d["vehicle"]["initial"]["on_ground"], at.on_ground);
  EXPECT_EQ(d["vehicle"]["control"]["drive_wheels"], "all");
  EXPECT_EQ(d["ground"]["normal"], nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_FALSE(d.contains("preset"));  // optional and meaningful only when given
}

TEST(Defaults, TypedValuesEqualTheStructDefaults) {
  const Scenario s = parseScenario(minimalDoc());
  ASSERT_EQ(s.vehicles.size(), 1u);
  const CarParams def;
  const CarParams& p = s.vehicles[0].params;
  EXPECT_EQ(p.rim_points, def.rim_points);
  EXPECT_DOUBLE_EQ(p.max_steer, def.max_steer);  // round trip through degrees
  EXPECT_EQ(p.rim_stiffness, def.rim_stiffness);
  EXPECT_EQ(s.options.contact.friction_iterations, ContactParams{}.friction_iterations);
}

TEST(Defaults, FilledDocumentIsAFixedPoint) {
  // validating what was simulated gives the same document: it can be saved
  // and rerun as is
  auto d = minimalDoc();
  d["ground"] = {{"type", "expression"}, {"expression", "z - 0.5*cos(x)"}};
  const Scenario once = parseScenario(d);
  const Scenario twice = parseScenario(once.document);
  EXPECT_EQ(once.document, twice.document);
}

TEST(Defaults, GivenValuesAreKept) {
  auto d = minimalDoc();
  d["vehicle"]["wheel_radius"] = 0.4;
  d["vehicle"]["initial"]["yaw_deg"] = 90;
  const Scenario s = parseScenario(d);
  EXPECT_EQ(s.document["vehicle"]["wheel_radius"], 0.4);
  EXPECT_EQ(s.vehicles[0].params.wheel_radius, 0.4);
  EXPECT_NEAR(s.vehicles[0].placement.yaw, std::acos(-1.0) / 2, 1e-15);
}

}  // namespace
}  // namespace groundsim::scenario::test
