// Every observation feature against its definition (docs/scenario.md,
// "Tasks"): cars placed with a known pose and speed, grounds with a known
// height. Observations are float32, hence the tolerances.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTol = 2e-6;  // float32 of values of order 1

nlohmann::json task(nlohmann::json observation) {
  return {{"observation", std::move(observation)}, {"goal", {10.0, 5.0}}};
}

TEST(Features, BodyFrameVelocityHeadingAndPositionOfACarPlacedWithKnownYawAndSpeed) {
  const double yaw = 30.0;
  Batch b(roadCarDoc(plane(), task({"position", "heading", "up_body", "velocity_body", "speed"}),
                     {{"position", {1.0, 2.0, 0.0}}, {"yaw_deg", yaw}, {"speed", 5.0}}),
          1);
  b.reset();
  EXPECT_NEAR(b.o("velocity_body.x"), 5.0, 5 * kTol);
  EXPECT_NEAR(b.o("velocity_body.y"), 0.0, kTol);
  EXPECT_NEAR(b.o("velocity_body.z"), 0.0, kTol);
  EXPECT_NEAR(b.o("speed"), 5.0, 5 * kTol);
  EXPECT_NEAR(b.o("heading.cos"), std::cos(yaw * kDeg), kTol);
  EXPECT_NEAR(b.o("heading.sin"), std::sin(yaw * kDeg), kTol);
  EXPECT_NEAR(b.o("position.x"), 1.0, kTol);
  EXPECT_NEAR(b.o("position.y"), 2.0, kTol);
  EXPECT_NEAR(b.o("up_body.x"), 0.0, kTol);
  EXPECT_NEAR(b.o("up_body.y"), 0.0, kTol);
  EXPECT_NEAR(b.o("up_body.z"), 1.0, kTol);
}

TEST(Features, UpBodyOnAnInclineIsTheTiltedVertical) {
  // aligned with the ground normal n = (sin a, 0, cos a) facing downhill
  // (+x): the body's x axis is (cos a, 0, -sin a), so e_z in the body frame
  // is (-sin a, 0, cos a)
  const double a = 10.0 * kDeg;
  Batch b(roadCarDoc({{"type", "incline"}, {"angle_deg", 10.0}, {"downhill", {1.0, 0.0}}}, task({"up_body"})), 1);
  b.reset();
  EXPECT_NEAR(b.o("up_body.x"), -std::sin(a), kTol);
  EXPECT_NEAR(b.o("up_body.y"), 0.0, kTol);
  EXPECT_NEAR(b.o("up_body.z"), std::cos(a), kTol);
}

TEST(Features, GoalInTheBodyFrameAndItsDistance) {
  const double yaw = 30.0 * kDeg, gx = 10.0 - 1.0, gy = 5.0 - 2.0;
  Batch b(roadCarDoc(plane(), task({"goal_body", "goal_distance"}),
                     {{"position", {1.0, 2.0, 0.0}}, {"yaw_deg", 30.0}}),
          1);
  b.reset();
  EXPECT_NEAR(b.o("goal_body.x"), gx * std::cos(yaw) + gy * std::sin(yaw), 1e-5);
  EXPECT_NEAR(b.o("goal_body.y"), -gx * std::sin(yaw) + gy * std::cos(yaw), 1e-5);
  EXPECT_NEAR(b.o("goal_distance"), std::hypot(gx, gy), 1e-5);
}

TEST(Features, HeightSamplesFollowTheGroundsAnalyticHeight) {
  const double A = 0.2, L = 8.0, yaw = 30.0 * kDeg;
  const std::vector<double> ahead = {1.0, 3.0}, lateral = {-1.0, 0.5};
  nlohmann::json t = task({"position", "heading", "height_samples"});
  t["height_samples"] = {{"ahead", ahead}, {"lateral", lateral}};
  Batch b(roadCarDoc({{"type", "bumps"}, {"amplitude", A}, {"wavelength_x", L}, {"wavelength_y", L}}, t,
                     {{"position", {1.0, 2.0, 0.0}}, {"yaw_deg", 30.0}}),
          1);
  b.reset();
  const double cx = b.o("position.x"), cy = b.o("position.y"), cz = b.o("position.z");
  // the grid follows the heading (the forward axis on the ground plane; the
  // car stands tilted on the bumps, so that is near the placement's yaw)
  const double c = b.o("heading.cos"), s = b.o("heading.sin");
  EXPECT_NEAR(std::atan2(s, c), yaw, 0.05);
  for (size_t i = 0; i < ahead.size(); ++i)
    for (size_t j = 0; j < lateral.size(); ++j) {
      const double x = cx + ahead[i] * c - lateral[j] * s, y = cy + ahead[i] * s + lateral[j] * c;
      const double z = A * std::sin(2 * std::numbers::pi * x / L) * std::sin(2 * std::numbers::pi * y / L);
      EXPECT_NEAR(b.o("height_samples." + std::to_string(i * lateral.size() + j)), z - cz, 2e-5) << i << "," << j;
    }
}

TEST(Features, RoadCarWheelSpinIsSpeedOverRadius) {
  Batch b(roadCarDoc(plane(), task({"wheel_spin"}), {{"speed", 8.0}}), 1);
  b.reset();
  for (const char* w : {"fl", "fr", "rl", "rr"}) EXPECT_NEAR(b.o(std::string("wheel_spin.") + w), 8.0 / 0.32, 1e-5);
}

TEST(Features, ReportCarWheelSpinIsRelativeToTheBody) {
  Batch b(reportCarDoc(plane(), task({"wheel_spin"}), {{"wheel_spin", 3.0}}), 1);
  b.reset();
  for (const char* w : {"fl", "fr", "rl", "rr"}) EXPECT_NEAR(b.o(std::string("wheel_spin.") + w), 3.0, 1e-5);
}

TEST(Features, ContactsAreZeroAtResetAndOneOnceTheCarStandsOnItsWheels) {
  Batch b(roadCarDoc(plane(), task({"wheel_contact", "wheel_slip", "suspension_travel", "time"})), 1);
  b.reset();
  for (const char* w : {"fl", "fr", "rl", "rr"}) EXPECT_EQ(b.o(std::string("wheel_contact.") + w), 0.0);
  b.step();
  for (const char* w : {"fl", "fr", "rl", "rr"}) {
    EXPECT_EQ(b.o(std::string("wheel_contact.") + w), 1.0);
    // at rest at design ride height: no slip, travel within the stops
    EXPECT_NEAR(b.o(std::string("wheel_slip.") + w), 0.0, 1e-3);
    EXPECT_LT(std::abs(b.o(std::string("suspension_travel.") + w)), 0.08);
  }
}

TEST(Features, DrivenWheelsSlipForwardUnderFullThrottle) {
  // the default road car drives its rear wheels: under full throttle from
  // 5 m/s their slip ratio is positive and larger than the free fronts'
  Batch b(roadCarDoc(plane(), task({"wheel_slip"}), {{"speed", 5.0}}), 1);
  b.reset();
  b.setAll({1.0f, 0.0f, 0.0f});
  for (int i = 0; i < 5; ++i) b.step();
  EXPECT_GT(b.o("wheel_slip.rl"), 0.0);
  EXPECT_GT(b.o("wheel_slip.rl"), std::abs(b.o("wheel_slip.fl")));
  EXPECT_GT(b.o("wheel_slip.rr"), std::abs(b.o("wheel_slip.fr")));
}

TEST(Features, TimeCountsControlPeriodsAndPreviousActionIsTheClippedAction) {
  nlohmann::json t = task({"time", "previous_action"});
  t["control_period"] = 5;
  Batch b(roadCarDoc(plane(), t), 1);
  b.reset();
  EXPECT_EQ(b.o("time"), 0.0);
  EXPECT_EQ(b.o("previous_action.throttle"), 0.0);
  b.setAll({0.25f, 7.0f, -3.0f});  // brake and steer beyond their bounds: clipped
  for (int i = 1; i <= 3; ++i) {
    b.step();
    EXPECT_NEAR(b.o("time"), i * 5 * 0.004, 1e-7);
  }
  EXPECT_EQ(b.o("previous_action.throttle"), 0.25f);
  EXPECT_EQ(b.o("previous_action.brake"), 1.0f);
  EXPECT_EQ(b.o("previous_action.steer"), -1.0f);
}

TEST(Features, BodyYawRateMatchesTheHeadingsChange) {
  // a steady turn: angular_velocity_body.z (the yaw rate on flat ground)
  // against the heading's change over one action
  nlohmann::json t = task({"heading", "angular_velocity_body"});
  t["control_period"] = 1;
  Batch b(roadCarDoc(plane(), t, {{"speed", 8.0}}), 1);
  b.reset();
  b.setAll({0.3f, 0.0f, 0.3f});
  for (int i = 0; i < 1000; ++i) b.step();
  const double psi0 = std::atan2(b.o("heading.sin"), b.o("heading.cos"));
  const double r0 = b.o("angular_velocity_body.z");
  b.step();
  const double psi1 = std::atan2(b.o("heading.sin"), b.o("heading.cos"));
  const double r1 = b.o("angular_velocity_body.z");
  ASSERT_GT(std::abs(r0), 0.05);  // it does turn
  EXPECT_NEAR(std::remainder(psi1 - psi0, 2 * std::numbers::pi) / 0.004, 0.5 * (r0 + r1), 0.02 * std::abs(r0));
}

TEST(Features, LayoutNamesEveryComponentWithBounds) {
  nlohmann::json t = task({"up_body", "wheel_contact", "previous_action"});
  t["action"] = {{"handbrake", true}};
  Batch b(roadCarDoc(plane(), t), 2);
  const Layout& l = b.layout();
  EXPECT_EQ(l.num_envs, 2);
  EXPECT_EQ(l.dt, 0.004);
  EXPECT_EQ(l.wheel_counts, std::vector<int>{4});
  EXPECT_EQ(l.action, (std::vector<std::string>{"throttle", "brake", "steer", "handbrake"}));
  EXPECT_EQ(l.obsSize(), 3 + 4 + 4);
  EXPECT_EQ(l.observation[3], "wheel_contact.fl");
  EXPECT_EQ(l.observation_high[3], 1.0f);
  EXPECT_EQ(l.observation.back(), "previous_action.handbrake");
  EXPECT_EQ(l.observation_low.size(), l.observation.size());
  EXPECT_EQ(l.scenario_hash.size(), 32u);
}

}  // namespace
}  // namespace groundsim::experiments::test
