// configs/sedan.json holds issue 9's figures, and a road car's keys and
// controls table are validated with path-named errors.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "scenario/scenario.hpp"
#include "scenario/scenario_error.hpp"
#include "sedan.hpp"

namespace groundsim::test {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(SedanConfig, HoldsTheIssueFigures) {
  const scenario::Scenario s = scenario::loadScenarioFile(std::string(GROUNDSIM_CONFIGS) + "/sedan.json");
  ASSERT_EQ(s.vehicles.size(), 1u);
  const RoadCarParams& p = s.vehicles[0].road;
  const RoadCarParams q = sedan();
  EXPECT_TRUE(s.vehicles[0].road_car);
  EXPECT_EQ(p.mass, 1500.0);
  EXPECT_EQ(p.wheelbase, 2.70);
  EXPECT_EQ(p.cg_to_front, 1.20);
  EXPECT_EQ(p.cg_height, 0.55);
  EXPECT_EQ(p.track, 1.55);
  EXPECT_EQ(p.inertia, Vec3(550, 2400, 2600));
  EXPECT_EQ(p.wheel_radius, 0.32);
  EXPECT_EQ(p.wheel_mass, 20.0);
  EXPECT_EQ(p.wheel_inertia, 1.0);
  EXPECT_EQ(p.suspension[0].ride_frequency, 1.3);
  EXPECT_EQ(p.suspension[1].ride_frequency, 1.4);
  EXPECT_EQ(p.suspension[0].damping_ratio, 0.3);
  for (int ax = 0; ax < 2; ++ax) {
    EXPECT_EQ(p.tyre[ax].vertical_stiffness, 2e5);
    EXPECT_EQ(p.tyre[ax].cornering_stiffness, q.tyre[ax].cornering_stiffness);
    EXPECT_EQ(p.tyre[ax].rolling_resistance, 0.012);
  }
  EXPECT_EQ(p.tyre[0].cornering_stiffness, 6e4);
  EXPECT_EQ(p.tyre[1].cornering_stiffness, 8e4);
  EXPECT_EQ(p.powertrain.gears.size(), 6u);
  EXPECT_EQ(p.powertrain.efficiency, 0.9);
  EXPECT_EQ(p.powertrain.drive, Drive::Rear);
  double peak = 0.0;  // peak power of the torque table: 110 kW
  for (double rpm = 900; rpm <= 6500; rpm += 1) peak = std::max(peak, engineTorque(p.powertrain, rpm * kPiRpm) * rpm * kPiRpm);
  EXPECT_NEAR(peak, 110e3, 0.01e3);
  EXPECT_EQ(p.aero.drag_area, 0.66);
  EXPECT_EQ(p.aero.air_density, 1.225);
  EXPECT_NEAR(p.steering.max_angle, 35.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_TRUE(p.brakes.abs);
  EXPECT_EQ(s.options.contact.friction, 1.0);
}

scenario::Scenario parseWith(const std::string& vehicle_extra) {
  return scenario::parseScenario(R"({"ground": {"type": "plane"}, "contact": {"friction": 1},
    "vehicle": {"kind": "road_car")" + vehicle_extra + "}}");
}

TEST(ControlTable, EachEntryHoldsWhatItDoesNotName) {
  const scenario::Scenario s = parseWith(R"(, "controls": [{"t": 0, "throttle": 1, "steer": 0.5},
      {"t": 6, "throttle": 0, "brake": 1}, {"t": 8, "gear": "R", "handbrake": true}])");
  const auto& rows = s.vehicles[0].controls;
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].t, 6.0);
  EXPECT_EQ(rows[1].controls.throttle, 0.0);
  EXPECT_EQ(rows[1].controls.brake, 1.0);
  EXPECT_EQ(rows[1].controls.steer, 0.5);  // held from the first row
  EXPECT_EQ(rows[2].controls.gear, CarControls::kReverse);
  EXPECT_TRUE(rows[2].controls.handbrake);
  EXPECT_EQ(rows[2].controls.brake, 1.0);
}

TEST(ControlTable, StepSceneAppliesRowsAtTheirTimes) {
  const scenario::Scenario s = parseWith(R"(, "controls": [{"t": 0, "throttle": 1}, {"t": 0.5, "throttle": 0, "brake": 1}])");
  scenario::Scene scene = scenario::buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  ASSERT_TRUE(scenario::stepScene(scene, sim, 10));
  EXPECT_EQ(sim.carControls(0).throttle, 1.0);
  while (sim.state().t < 0.5 - 1e-9) ASSERT_TRUE(scenario::stepScene(scene, sim, 1));
  ASSERT_TRUE(scenario::stepScene(scene, sim, 1));
  EXPECT_EQ(sim.carControls(0).brake, 1.0);
  EXPECT_EQ(sim.carControls(0).throttle, 0.0);
}

std::string errorsOf(const std::string& extra) {
  try {
    parseWith(extra);
  } catch (const scenario::ScenarioError& e) {
    return e.what();
  }
  return "";
}

TEST(ControlTable, HostileEntriesNameTheirPath) {
  EXPECT_NE(errorsOf(R"(, "controls": [{"t": 0, "throttle": 2}])").find("/vehicle/controls/0/throttle"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "controls": [{"t": 3}, {"t": 1}])").find("/vehicle/controls/1/t"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "controls": [{"throttle": 1}])").find("/vehicle/controls/0/t"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "controls": [{"t": 0, "gear": "7"}])").find("/vehicle/controls/0/gear"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "controls": [{"t": 0, "thrott": 1}])").find("/vehicle/controls/0/thrott"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "controls": {"t": 0})").find("/vehicle/controls"), std::string::npos);
}

TEST(RoadCarKeys, HostileFiguresNameTheirPath) {
  EXPECT_NE(errorsOf(R"(, "cg_to_front": 3.0)").find("/vehicle/cg_to_front"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "mass": -1)").find("/vehicle/mass"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "tyres": {"front": {"sliding_ratio": 1.5}})").find("/vehicle/tyres/front/sliding_ratio"),
            std::string::npos);
  EXPECT_NE(errorsOf(R"(, "powertrain": {"torque_rpm": [1000, 900], "torque": [1, 2]})").find("/vehicle/powertrain/torque_rpm"),
            std::string::npos);
  EXPECT_NE(errorsOf(R"(, "powertrain": {"drive": "sideways"})").find("/vehicle/powertrain/drive"), std::string::npos);
  EXPECT_NE(errorsOf(R"(, "rim_points": 20)").find("/vehicle/rim_points"), std::string::npos);  // not a road car key
}

}  // namespace
}  // namespace groundsim::test
