// The state streams' JSON: each quantity to its documented decimals by
// default, exactly with --exact, N digits with --digits; the fields protocol
// 2 added (epoch, error_estimate, server_id) on every message that has them;
// the precision's name as the file says it, read back, and names that are
// not one refused.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "protocol/message_json.hpp"

namespace groundsim::record {
namespace {

groundsim::state_t sample() {
  groundsim::state_t m{};
  m.utime = 1234000;
  m.seq = 617;
  m.session_id = "3F2A0C11";
  m.t = 1.234;
  m.tick = 1234;
  m.energy = 12345.678912345;
  m.epoch = 3;
  m.error_estimate = 0.012345678901234;
  m.nvehicles = 1;
  m.vehicles.resize(1);
  auto& v = m.vehicles[0];
  v.name = "car";
  v.position[0] = 12.3456785123;
  v.position[1] = -0.00049;  // under half a millimetre: 0
  v.position[2] = 0.4;
  v.orientation[0] = 0.99999999991;
  v.orientation[1] = -1.23456789e-3;
  v.velocity[0] = 1e-300;
  v.angular_velocity[2] = -2.5e-4;  // a quarter of a unit below zero: 0, not -0
  v.speed = 9.87654321;
  v.wheel_count = 4;
  v.wheel_spin[0] = 31.4159265;
  v.normal_force[0] = 3456.78951;
  v.friction_force[0] = 1e300;  // past 9e15 units: written exactly
  v.slip[0] = 0.0123456;
  return m;
}

TEST(MessageJson, FieldsAreWrittenToTheirDecimals) {
  setPrecision(Precision::Fields);
  const auto j = nlohmann::json::parse(toJson(sample()));
  const auto& v = j["vehicles"][0];
  EXPECT_EQ(v["position"][0].dump(), "12.346");   // a millimetre
  EXPECT_EQ(v["position"][1].dump(), "0");        // not -0
  EXPECT_EQ(v["position"][2].dump(), "0.4");      // trailing zeros dropped
  EXPECT_EQ(v["orientation"][0].dump(), "1");     // 1e-4
  EXPECT_EQ(v["orientation"][1].dump(), "-0.0012");
  EXPECT_EQ(v["velocity"][0].dump(), "0");
  EXPECT_EQ(v["angular_velocity"][2].dump(), "0");
  EXPECT_EQ(v["speed"].dump(), "9.877");
  EXPECT_EQ(v["wheel_spin"][0].dump(), "31.42");  // 0.01 rad/s
  EXPECT_EQ(v["normal_force"][0].dump(), "3457"); // a newton
  EXPECT_EQ(v["friction_force"][0].get<double>(), 1e300);
  EXPECT_EQ(v["slip"][0].dump(), "0.012");
  EXPECT_EQ(j["energy"].dump(), "12346");
  // time and the estimate stay exact
  EXPECT_EQ(j["t"].get<double>(), 1.234);
  EXPECT_EQ(j["error_estimate"].get<double>(), 0.012345678901234);
  // the text itself, not just the doubles it reads back as
  const std::string text = toJson(sample());
  EXPECT_NE(text.find("\"orientation\":[1,-0.0012,0,0]"), std::string::npos) << text;
  EXPECT_NE(text.find("\"position\":[12.346,0,0.4]"), std::string::npos) << text;
  EXPECT_EQ(precisionName(), "fields-1");
}

TEST(MessageJson, ExactWritesEveryDoubleAsItIs) {
  setPrecision(Precision::Exact);
  const groundsim::state_t m = sample();
  const auto j = nlohmann::json::parse(toJson(m));
  const auto& v = j["vehicles"][0];
  for (int i = 0; i < 3; ++i) EXPECT_EQ(v["position"][i].get<double>(), m.vehicles[0].position[i]);
  EXPECT_EQ(v["velocity"][0].get<double>(), 1e-300);
  EXPECT_EQ(j["energy"].get<double>(), m.energy);
  EXPECT_EQ(precisionName(), "exact");
}

TEST(MessageJson, DigitsAreSignificantDigits) {
  setPrecision(Precision::Digits, 4);
  const auto j = nlohmann::json::parse(toJson(sample()));
  EXPECT_EQ(j["vehicles"][0]["position"][0].get<double>(), 12.35);
  EXPECT_EQ(j["energy"].get<double>(), 12350.0);
  EXPECT_EQ(precisionName(), "digits-4");
  setPrecision(Precision::Fields);
}

TEST(MessageJson, ProtocolTwoFieldsAreCarried) {
  setPrecision(Precision::Fields);
  const auto s = nlohmann::json::parse(toJson(sample()));
  EXPECT_EQ(s["epoch"], 3);
  groundsim::car_state_t c{};
  c.epoch = 4;
  EXPECT_EQ(nlohmann::json::parse(toJson(c))["epoch"], 4);
  groundsim::contact_state_t k{};
  k.epoch = 5;
  EXPECT_EQ(nlohmann::json::parse(toJson(k))["epoch"], 5);
  groundsim::applied_t a{};
  a.epoch = 6;
  EXPECT_EQ(nlohmann::json::parse(toJson(a))["epoch"], 6);
  groundsim::event_t e{};
  e.epoch = 7;
  e.server_id = "a1b2c3";
  const auto ej = nlohmann::json::parse(toJson(e));
  EXPECT_EQ(ej["epoch"], 7);
  EXPECT_EQ(ej["server_id"], "a1b2c3");
  // and each schema names them
  for (const char* schema : {stateSchema(), carStateSchema(), contactStateSchema(), eventSchema(), appliedSchema()})
    EXPECT_TRUE(nlohmann::json::parse(schema)["properties"].contains("epoch")) << schema;
  EXPECT_TRUE(nlohmann::json::parse(stateSchema())["properties"].contains("error_estimate"));
  EXPECT_TRUE(nlohmann::json::parse(eventSchema())["properties"].contains("server_id"));
}

TEST(MessageJson, AppliedEntriesAreExactWhateverThePrecision) {
  setPrecision(Precision::Fields);
  groundsim::applied_t a{};
  a.throttle = 0.123456789012345;
  a.wheel_torque[0] = 123.456789012345;
  const auto j = nlohmann::json::parse(toJson(a));
  EXPECT_EQ(j["throttle"].get<double>(), 0.123456789012345);
  EXPECT_EQ(j["wheel_torque"][0].get<double>(), 123.456789012345);
}

TEST(MessageJson, PrecisionNamesReadBack) {
  Precision p{};
  int d = 0;
  EXPECT_TRUE(parsePrecision("fields-1", &p, &d));
  EXPECT_EQ(p, Precision::Fields);
  EXPECT_TRUE(parsePrecision("exact", &p, &d));
  EXPECT_EQ(p, Precision::Exact);
  EXPECT_TRUE(parsePrecision("digits-9", &p, &d));
  EXPECT_EQ(p, Precision::Digits);
  EXPECT_EQ(d, 9);
  // json_digits of files from before
  EXPECT_TRUE(parsePrecision("17", &p, &d));
  EXPECT_EQ(p, Precision::Exact);
  EXPECT_TRUE(parsePrecision("7", &p, &d));
  EXPECT_EQ(p, Precision::Digits);
  EXPECT_EQ(d, 7);
  for (const char* bad : {"", "fields-2", "fields", "digits-0", "digits-17", "digits-9x", "0", "-3", "exactly"})
    EXPECT_FALSE(parsePrecision(bad, &p, &d)) << bad;
}

}  // namespace
}  // namespace groundsim::record
