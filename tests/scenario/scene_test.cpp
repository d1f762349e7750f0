// Scenario -> Scene: model, initial controls, and the problems only visible
// while building.
#include <gtest/gtest.h>

#include "physics/integrators/integrator.hpp"
#include "physics/simulator.hpp"
#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

std::vector<Issue> buildIssues(const nlohmann::json& d) {
  try {
    buildScene(parseScenario(d));
  } catch (const ScenarioError& e) {
    return e.issues();
  }
  ADD_FAILURE() << "scene was built";
  return {};
}

TEST(Scene, OneCarWithItsSettings) {
  auto d = minimalDoc();
  d["physics"]["dt"] = 1e-4;
  d["contact"]["friction"] = 0.8;
  const Scene scene = buildScene(parseScenario(d));
  ASSERT_EQ(scene.cars.size(), 1u);
  EXPECT_EQ(scene.vehicle_names, std::vector<std::string>{"car"});
  const Model& m = *scene.built.model;
  EXPECT_EQ(m.opt.dt, 1e-4);
  EXPECT_EQ(m.opt.contact.friction, 0.8);
  EXPECT_EQ(m.wheels.size(), 4u);
  EXPECT_EQ(scene.built.initial.controls.size(), m.wheels.size());
}

TEST(Scene, ControlsGoToTheChosenWheels) {
  auto d = minimalDoc();
  d["vehicle"]["control"] = {{"drive_torque", 1.5}, {"drive_wheels", "rear"}, {"brake_torque", 0.2}};
  const Scene scene = buildScene(parseScenario(d));
  const CarHandle& car = scene.cars[0];
  const auto& c = scene.built.initial.controls;
  for (int k = 0; k < 4; ++k) {
    const WheelControl& w = c.at(static_cast<size_t>(car.wheels[k]));
    EXPECT_EQ(w.drive_torque, k >= 2 ? 1.5 : 0.0) << "wheel " << k;  // fl, fr, rl, rr
    EXPECT_EQ(w.brake_torque, 0.2);
  }
}

TEST(Scene, SeveralVehiclesInDocumentOrder) {
  auto d = nlohmann::json::parse(R"({"ground": {"type": "plane"}, "vehicles": [
      {"name": "a", "control": {"drive_torque": 1}},
      {"name": "b", "initial": {"position": [0, 10, 0]}}]})");
  const Scene scene = buildScene(parseScenario(d));
  ASSERT_EQ(scene.cars.size(), 2u);
  EXPECT_EQ(scene.vehicle_names, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(scene.built.initial.controls.at(scene.cars[0].wheels[0]).drive_torque, 1.0);
  EXPECT_EQ(scene.built.initial.controls.at(scene.cars[1].wheels[0]).drive_torque, 0.0);
  Simulator sim(scene.built.model, scene.built.initial);
  EXPECT_TRUE(sim.step(100));
}

TEST(Scene, OverlappingVehiclesAreRefused) {
  auto d = nlohmann::json::parse(R"({"ground": {"type": "plane"}, "vehicles": [
      {"name": "a"}, {"name": "b", "initial": {"position": [1, 0, 0]}}]})");
  EXPECT_TRUE(hasIssue(buildIssues(d), "/vehicles/1/initial/position", "overlaps vehicle \"a\""));
}

// Footprints are rectangles along each heading: sedans (4.7 x 1.8 m body
// box, centred on the axles' midpoint 0.15 m behind the centre of mass)
// may stand side by side or nose to tail, not inside each other's box.
TEST(Scene, RoadCarFootprintsAreTheirBodyBoxes) {
  const auto pair = [](double x, double y, double yaw_deg) {
    nlohmann::json d = {{"ground", {{"type", "plane"}}},
                        {"vehicles",
                         {{{"name", "a"}, {"kind", "road_car"}},
                          {{"name", "b"},
                           {"kind", "road_car"},
                           {"initial", {{"position", {x, y, 0}}, {"yaw_deg", yaw_deg}}}}}}};
    try {
      buildScene(parseScenario(d));
      return false;
    } catch (const ScenarioError& e) {
      EXPECT_TRUE(hasIssue(e.issues(), "/vehicles/1/initial/position", "overlaps vehicle \"a\""));
      return true;
    }
  };
  EXPECT_FALSE(pair(0.0, 1.85, 0));   // side by side, 5 cm apart
  EXPECT_TRUE(pair(0.0, 1.75, 0));    // 5 cm into each other
  EXPECT_FALSE(pair(4.75, 0.0, 0));   // nose to tail
  EXPECT_TRUE(pair(4.65, 0.0, 0));
  // turned across: b's tail (2.5 m behind its centre) meets a's side (0.9)
  EXPECT_FALSE(pair(0.0, 3.45, 90));
  EXPECT_TRUE(pair(0.0, 3.35, 90));
  // turned 45 degrees: the footprints' circles (2.66 m each) overlap, the
  // rectangles only once b's corner reaches a's side
  EXPECT_FALSE(pair(0.0, 3.5, 45));
  EXPECT_TRUE(pair(0.0, 3.1, 45));
}

TEST(Scene, EveryIntegratorBuildsWithAFrictionModelItCanIntegrate) {
  for (const char* name : {"semi_implicit_euler", "velocity_verlet", "rk4", "implicit_euler", "adaptive"}) {
    auto d = minimalDoc();
    d["physics"]["integrator"] = name;
    d["contact"]["friction_model"] = "regularized";
    EXPECT_NO_THROW(buildScene(parseScenario(d))) << name;
  }
  for (const char* name : {"semi_implicit_euler", "velocity_verlet"}) {
    auto d = minimalDoc();
    d["physics"]["integrator"] = name;  // time-steppers own the stick-slip solve
    EXPECT_NO_THROW(buildScene(parseScenario(d))) << name;
  }
  for (const char* name : {"rk4", "implicit_euler", "adaptive"})
    for (const char* friction : {"stick_slip", "sign"}) {
      auto d = minimalDoc();
      d["physics"]["integrator"] = name;
      d["contact"]["friction_model"] = friction;
      EXPECT_TRUE(hasIssue(buildIssues(d), "/contact/friction_model", "\"regularized\"")) << name << friction;
    }
}

TEST(Scene, EachBuildHasItsOwnGround) {
  // an expression ground holds parser state: scenes must not share it
  auto d = minimalDoc();
  d["ground"] = {{"type", "expression"}, {"expression", "z - 0.5*cos(x)"}};
  const Scenario s = parseScenario(d);
  EXPECT_NE(buildScene(s).built.model->ground.get(), buildScene(s).built.model->ground.get());
}

TEST(Scene, CarSitsOnTheGround) {
  auto d = minimalDoc();
  d["ground"] = {{"type", "incline"}, {"angle_deg", 20}};
  const Scene scene = buildScene(parseScenario(d));
  Simulator sim(scene.built.model, scene.built.initial);
  // placed with wheels touching: after a short settle nothing has diverged
  // and the body has not fallen through
  ASSERT_TRUE(sim.step(2000));
  const Vec3 x = bodyPos(sim.state().y, scene.cars[0].body);
  Vec3 grad;
  EXPECT_GT(scene.built.model->ground->eval(x, &grad), 0.0);
}

}  // namespace
}  // namespace groundsim::scenario::test
