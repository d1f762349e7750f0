// Every kind of invalid input is reported with its JSON pointer path and
// reason, and all problems of a document are reported together.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

TEST(Validation, MinimalDocumentIsValid) { EXPECT_NO_THROW(parseScenario(minimalDoc())); }

TEST(Validation, OutOfRangeNamesPathBoundAndValue) {
  auto d = minimalDoc();
  d["vehicle"]["wheel_radius"] = -1;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/wheel_radius", "must be > 0, got -1"));
}

TEST(Validation, WrongTypeNamesExpectedAndActual) {
  auto d = minimalDoc();
  d["contact"]["friction"] = "high";
  EXPECT_TRUE(hasIssue(issuesOf(d), "/contact/friction", "expected a number, got string"));
  d = minimalDoc();
  d["vehicle"]["body_contact"] = 1;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/body_contact", "expected true or false"));
  d = minimalDoc();
  d["physics"] = 5;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics", "expected an object"));
  d = minimalDoc();
  d["vehicles"] = {{"name", "a"}};  // an object where an array belongs
  d.erase("vehicle");
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicles", "expected an array"));
}

TEST(Validation, NegativeMassesAreRejected) {
  auto d = minimalDoc();
  d["vehicle"]["body_mass"] = -1.0;
  d["vehicle"]["wheel_mass"] = 0.0;
  const auto issues = issuesOf(d);
  EXPECT_TRUE(hasIssue(issues, "/vehicle/body_mass", "must be > 0"));
  EXPECT_TRUE(hasIssue(issues, "/vehicle/wheel_mass", "must be > 0"));
}

TEST(Validation, HugeValuesAreRejectedWithTheBound) {
  auto d = minimalDoc();
  d["vehicle"]["body_mass"] = 1e308;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/body_mass", "in magnitude, got 1e+308"));
}

TEST(Validation, UnrepresentableNumbersInTextAreRejected) {
  // JSON has no NaN or inf; 1e999 overflows while parsing
  const auto issues = issuesOf(std::string(R"({"ground": {"type": "plane"}, "vehicle": {"body_mass": 1e999}})"));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].path, "");
  EXPECT_NE(issues[0].message.find("1e999"), std::string::npos) << issues[0].message;
  EXPECT_TRUE(hasIssue(issuesOf(std::string(R"({"duration": NaN})")), "", "malformed JSON"));
}

TEST(Validation, StepBounds) {
  for (double dt : {0.0, -1e-4, 0.5}) {
    auto d = minimalDoc();
    d["physics"]["dt"] = dt;
    EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/dt", "must be")) << dt;
  }
  auto d = minimalDoc();
  d["physics"]["dt"] = 0.01;
  d["output_rate"] = 1000;  // faster than one frame per step
  EXPECT_TRUE(hasIssue(issuesOf(d), "/output_rate", "1/physics.dt"));
}

TEST(Validation, IntegersMustBeWhole) {
  auto d = minimalDoc();
  d["vehicle"]["rim_points"] = 2.5;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/rim_points", "expected an integer, got 2.5"));
  d["vehicle"]["rim_points"] = 2;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/rim_points", "must be >= 3"));
}

TEST(Validation, ChoicesListTheAllowedValues) {
  auto d = minimalDoc();
  d["contact"]["friction_model"] = "coulomb";
  EXPECT_TRUE(hasIssue(issuesOf(d), "/contact/friction_model", "\"stick_slip\""));
  d = minimalDoc();
  d["physics"]["integrator"] = "rk5";
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/integrator", "did you mean \"rk4\""));
}

TEST(Validation, UnknownKeysAreErrorsWithASuggestion) {
  auto d = minimalDoc();
  d["vehicle"]["whel_radius"] = 0.5;
  d["zzz_unrelated"] = 1;
  const auto issues = issuesOf(d);
  EXPECT_TRUE(hasIssue(issues, "/vehicle/whel_radius", "unknown key (did you mean \"wheel_radius\"?)"));
  EXPECT_TRUE(hasIssue(issues, "/zzz_unrelated", "unknown key"));
  EXPECT_FALSE(hasIssue(issues, "/zzz_unrelated", "did you mean"));
}

TEST(Validation, KeysOfAnotherGroundKindAreUnknown) {
  auto d = minimalDoc();
  d["ground"]["angle_deg"] = 10;  // an incline key on a plane
  EXPECT_TRUE(hasIssue(issuesOf(d), "/ground/angle_deg", "unknown key"));
}

TEST(Validation, MissingRequiredKeys) {
  auto issues = issuesOf(nlohmann::json::object());
  EXPECT_TRUE(hasIssue(issues, "/ground", "missing required key"));
  EXPECT_TRUE(hasIssue(issues, "/vehicle", "missing required key"));
  auto d = minimalDoc();
  d["ground"] = {{"type", "incline"}};
  EXPECT_TRUE(hasIssue(issuesOf(d), "/ground/angle_deg", "missing required key"));
  d["ground"] = nlohmann::json::object();
  EXPECT_TRUE(hasIssue(issuesOf(d), "/ground/type", "missing required key"));
}

TEST(Validation, VehicleOrVehicles) {
  auto d = minimalDoc();
  d["vehicles"] = nlohmann::json::array({nlohmann::json::object()});
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicles", "not both"));

  d.erase("vehicle");
  d["vehicles"] = nlohmann::json::array();
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicles", "at least one"));

  d["vehicles"] = nlohmann::json::parse(R"([{"name": "a"}, {"name": "a"}, {}])");
  const auto issues = issuesOf(d);
  EXPECT_TRUE(hasIssue(issues, "/vehicles/1/name", "duplicate"));
  EXPECT_TRUE(hasIssue(issues, "/vehicles/2/name", "missing required key"));
}

TEST(Validation, VectorsCheckLengthAndElements) {
  auto d = minimalDoc();
  d["physics"]["gravity"] = {0, 0};
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/gravity", "expected 3 numbers, got 2"));
  d["physics"]["gravity"] = nlohmann::json::array({0, 0, "down"});
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/gravity/2", "expected a number, got string"));
}

TEST(Validation, SteeringWithinTheVehiclesLimit) {
  auto d = minimalDoc();
  d["vehicle"]["max_steer_deg"] = 20;
  d["vehicle"]["control"]["steer_deg"] = 30;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/control/steer_deg", "max_steer_deg"));
}

TEST(Validation, PresetValueIsChecked) {
  auto d = minimalDoc();
  d["preset"] = "turbo";
  EXPECT_TRUE(hasIssue(issuesOf(d), "/preset", "must be one of"));
  d["preset"] = "fast";
  EXPECT_EQ(parseScenario(d).preset, "fast");
  EXPECT_EQ(parseScenario(d).document["preset"], "fast");
}

TEST(Validation, EveryProblemIsReportedAtOnce) {
  auto d = minimalDoc();
  d["vehicle"]["wheel_radius"] = -1;
  d["contact"]["friction"] = "x";
  d["physics"]["dt"] = 1.0;
  d["vehicle"]["initial"]["clearence"] = 0.1;
  const auto issues = issuesOf(d);
  EXPECT_EQ(issues.size(), 4u) << listed(issues);
}

TEST(Validation, MalformedTextNamesTheBytePosition) {
  const std::string text = R"({"ground": {"type": "plane"} "vehicle": {}})";  // missing comma
  const auto issues = issuesOf(text);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].path, "");
  EXPECT_NE(issues[0].message.find("at byte"), std::string::npos) << issues[0].message;
  EXPECT_TRUE(hasIssue(issuesOf(std::string("{\"ground\": {")), "", "malformed JSON"));  // truncated
  EXPECT_TRUE(hasIssue(issuesOf(std::string("  \n")), "", "empty"));
  EXPECT_TRUE(hasIssue(issuesOf(std::string("[1, 2]")), "", "expected an object, got array"));
}

class FileErrors : public ::testing::Test {
 protected:
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("scenario_file_test_" + std::to_string(::getpid()));
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }
  std::vector<Issue> loadIssues(const std::string& path) {
    try {
      loadScenarioFile(path);
    } catch (const ScenarioError& e) {
      return e.issues();
    }
    ADD_FAILURE() << path << " was accepted";
    return {};
  }
};

TEST_F(FileErrors, MissingEmptyAndDirectoryNameTheFile) {
  const std::string missing = (dir / "nope.json").string();
  EXPECT_TRUE(hasIssue(loadIssues(missing), "", missing));
  const std::string empty = (dir / "empty.json").string();
  std::ofstream(empty).close();
  EXPECT_TRUE(hasIssue(loadIssues(empty), "", "empty"));
  EXPECT_TRUE(hasIssue(loadIssues(empty), "", empty));
  EXPECT_TRUE(hasIssue(loadIssues(dir.string()), "", "directory"));
}

TEST_F(FileErrors, UnnamedScenarioIsCalledAfterItsFile) {
  const std::string path = (dir / "my_scene.json").string();
  std::ofstream(path) << minimalDoc().dump();
  EXPECT_EQ(loadScenarioFile(path).name, "my_scene");
}

}  // namespace
}  // namespace groundsim::scenario::test
