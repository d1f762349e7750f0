// The model budget: counts estimated from the specs equal the models the
// builders make, and every limit is refused at validation, before anything
// is built, with the path, the count, the limit and the flag that raises it.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

nlohmann::json withVehicle(const nlohmann::json& vehicle) {
  auto d = minimalDoc();
  d["vehicle"] = vehicle;
  return d;
}

void expectEstimateMatchesModel(const nlohmann::json& d) {
  const Scenario s = parseScenario(d);
  const ModelSize e = estimateModelSize(s);
  const auto scene = buildScene(s);  // kept: the model lives as long as the scene's shared_ptr
  const Model& m = *scene.built.model;
  const std::string what = d.dump();
  EXPECT_EQ(e.bodies, static_cast<long long>(m.bodies.size())) << what;
  EXPECT_EQ(e.points, static_cast<long long>(m.points.size())) << what;
  EXPECT_EQ(e.particles, static_cast<long long>(m.particles.size())) << what;
  EXPECT_EQ(e.springs, static_cast<long long>(m.springs.size())) << what;
  EXPECT_EQ(e.contact_points, static_cast<long long>(m.contact_points.size())) << what;
  EXPECT_EQ(e.state, static_cast<long long>(m.stateSize())) << what;
}

TEST(Budget, EstimateEqualsTheBuiltModelForEveryWheelKind) {
  for (const char* model : {"rim_points", "circle", "deformable"})
    for (const char* coupling : {"rim_springs", "bearing"})
      for (bool body_contact : {true, false})
        expectEstimateMatchesModel(withVehicle({{"wheel_model", model},
                                                {"coupling", coupling},
                                                {"body_contact", body_contact},
                                                {"rim_points", 7}}));
  for (const char* model : {"rim_points", "circle"})
    expectEstimateMatchesModel(withVehicle({{"kind", "wheel"}, {"wheel_model", model}, {"rim_points", 9}}));
  auto two = minimalDoc();
  two.erase("vehicle");
  two["vehicles"] = {{{"name", "a"}, {"wheel_model", "deformable"}, {"rim_points", 5}},
                     {{"name", "b"}, {"initial", {{"position", {10, 0, 0}}}}}};
  expectEstimateMatchesModel(two);
}

// A road car is one body of six mass points with twenty wheel states and no
// springs or contact points (physics/build/road_car_builder.cpp): the estimate
// did not know the kind and counted the report car's 4 wheels instead.
TEST(Budget, EstimateEqualsTheBuiltModelForRoadCars) {
  const nlohmann::json sedan = nlohmann::json::parse(std::ifstream(std::string(GROUNDSIM_SOURCE_DIR) + "/configs/sedan.json"));
  expectEstimateMatchesModel(sedan);
  const Scenario s = parseScenario(sedan);
  const ModelSize e = estimateModelSize(s);
  EXPECT_EQ(e.bodies, 1);
  EXPECT_EQ(e.springs, 0);
  EXPECT_EQ(e.state, 13 + 20);
  // a sedan beside a report car and a lone wheel, and two sedans
  auto mixed = minimalDoc();
  mixed.erase("vehicle");
  mixed["vehicles"] = {sedan["vehicle"], {{"name", "report"}, {"initial", {{"position", {10, 0, 0}}}}},
                       {{"name", "w"}, {"kind", "wheel"}, {"initial", {{"position", {-10, 0, 0}}}}}};
  mixed["vehicles"][0]["name"] = "sedan";
  expectEstimateMatchesModel(mixed);
  auto two = minimalDoc();
  two.erase("vehicle");
  two["vehicles"] = {{{"name", "a"}, {"kind", "road_car"}},
                     {{"name", "b"}, {"kind", "road_car"}, {"initial", {{"position", {0, 10, 0.55}}}}}};
  expectEstimateMatchesModel(two);
  EXPECT_EQ(estimateModelSize(parseScenario(two)).state, 2 * (13 + 20));
}

TEST(Budget, TooManyVehiclesIsRefusedBeforeReadingThem) {
  auto d = minimalDoc();
  d.erase("vehicle");
  d["vehicles"] = nlohmann::json::array();
  for (int i = 0; i < 50000; ++i) d["vehicles"].push_back(nlohmann::json::object());  // not even named
  const auto issues = issuesOf(d);
  ASSERT_EQ(issues.size(), 1u) << listed(issues);
  EXPECT_EQ(issues[0].str(), "/vehicles: 50000 vehicles, at most 64 (groundsim run --max-vehicles)");
  Budget server;
  server.source = "server";
  server.max_vehicles = 32;
  const auto e = errorOf(d, server);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->issues().front().str(), "/vehicles: 50000 vehicles, at most 32 (server --max-vehicles)");
}

TEST(Budget, EightDeformableCarsOfTenThousandRimPointsAreRefused) {
  // 869 bytes that took 5 s and 1.39 GB to build
  auto d = minimalDoc();
  d.erase("vehicle");
  for (int i = 0; i < 8; ++i)
    d["vehicles"].push_back({{"name", "c" + std::to_string(i)}, {"wheel_model", "deformable"}, {"rim_points", 10000},
                             {"initial", {{"position", {20 * i, 0, 0}}}}});
  const auto issues = issuesOf(d);
  EXPECT_TRUE(hasIssue(issues, "/vehicles", "960128 points, at most 200000 (groundsim run --max-points)"));
  EXPECT_TRUE(hasIssue(issues, "/vehicles", "1920064 springs, at most 400000 (groundsim run --max-springs)"));
  EXPECT_TRUE(hasIssue(issues, "/vehicles", "320000 particles, at most 100000"));
  EXPECT_TRUE(hasIssue(issues, "/vehicles", "state would have 1920520 numbers"));
  // raised limits accept it (counted, not built: the test stays cheap)
  Budget big;
  big.max_points = big.max_springs = big.max_particles = big.max_state = 10000000;
  big.max_work = 1e15;
  EXPECT_FALSE(errorOf(d, big)) << errorOf(d, big)->what();
}

TEST(Budget, ImplicitEulerOnAHugeStateIsRefused) {
  // 200 bytes that asked for a 461 GB Jacobian and aborted with bad_alloc
  auto d = withVehicle({{"wheel_model", "deformable"}, {"rim_points", 10000}});
  d["physics"]["integrator"] = "implicit_euler";
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/integrator",
                       "factors a dense 240065 x 240065 matrix every step"));
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/integrator", "at most 2000 (groundsim run --max-implicit-state)"));
  d["vehicle"]["rim_points"] = 20;  // a state of 545: 1.4e8 work units a step, with its LU
  d["physics"]["dt"] = 1e-3;
  EXPECT_NO_THROW(parseScenario(d));
}

TEST(Budget, StepsAreBounded) {
  auto d = minimalDoc();
  d["physics"]["dt"] = 1e-9;
  d["duration"] = 1e6;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/duration", "= 1000000000000000 steps, at most 1000000000 (groundsim run --max-steps)"));
  d["physics"]["dt"] = 1e-4;
  d["duration"] = 100;
  d["physics"]["substeps"] = 10000;  // substeps count: 1e10 integrator steps
  EXPECT_TRUE(hasIssue(issuesOf(d), "/duration", "x 10000 substeps = 10000000000 steps"));
}

TEST(Budget, StepBelowOneNanosecondIsRefused) {
  // 1e-20 used to run 0 steps and report "health ok"
  auto d = minimalDoc();
  d["physics"]["dt"] = 1e-20;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/physics/dt", "must be >= 1e-09, got 1e-20"));
}

TEST(Budget, WorkIsBounded) {
  // 1e8 steps of a 10000-rim-point car: within max_steps, not within max_work
  auto d = withVehicle({{"rim_points", 10000}});
  d["physics"]["dt"] = 1e-4;
  d["duration"] = 1e4;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/duration", "at most 1000000000000 (groundsim run --max-work)"));
}

TEST(Budget, RunLengthOfAnotherDuration) {
  const Scenario s = parseScenario(minimalDoc());
  EXPECT_NO_THROW(checkRunLength(s, -1.0, Budget{}));  // until stopped: paced, not counted
  EXPECT_NO_THROW(checkRunLength(s, 100.0, Budget{}));
  EXPECT_THROW(checkRunLength(s, 1e6, Budget{}), ScenarioError);  // 2e10 steps at dt 5e-5
}

TEST(Budget, ExpressionLengthIsBoundedBeforeParsing) {
  auto d = minimalDoc();
  std::string e = "z";
  for (int i = 0; i < 2000; ++i) e += "+0";
  d["ground"] = {{"type", "expression"}, {"expression", e}};
  EXPECT_NO_THROW(parseScenario(d));  // 4001 characters: within the default 4096
  Budget b;
  b.max_expression_length = 100;
  const auto err = errorOf(d, b);
  ASSERT_TRUE(err);
  EXPECT_EQ(err->issues().front().str(),
            "/ground/expression: 4001 characters, at most 100 (groundsim run --max-expression-length)");
}

TEST(Budget, OverlapsAreReportedOncePerVehicleAndCapped) {
  // 1,000 vehicles on one spot made an 83 MB report of 499,500 pairs
  auto d = minimalDoc();
  d.erase("vehicle");
  for (int i = 0; i < 1000; ++i) d["vehicles"].push_back({{"name", "v" + std::to_string(i)}});
  Budget b;
  b.max_vehicles = 1000;
  const Scenario s = parseScenario(d, b);
  try {
    buildScene(s);
    FAIL() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.issues().size(), kMaxListedIssues);
    EXPECT_EQ(e.omitted(), 999u - kMaxListedIssues);  // each vehicle after the first, once
    EXPECT_TRUE(hasIssue(e.issues(), "/vehicles/1/initial/position", "overlaps vehicle \"v0\""));
    EXPECT_LT(std::string(e.what()).size(), 4000u);
  }
}

TEST(Budget, VehiclesOnAGridDoNotOverlap) {
  auto d = minimalDoc();
  d.erase("vehicle");
  for (int i = 0; i < 64; ++i)
    d["vehicles"].push_back({{"name", "v" + std::to_string(i)},
                             {"wheel_model", "circle"},
                             {"initial", {{"position", {6.0 * (i % 8), 6.0 * (i / 8), 0}}}}});
  EXPECT_NO_THROW(buildScene(parseScenario(d)));
  // 1 m across and 2 m along from v55: inside its 5 x 2.5 m footprint
  d["vehicles"][63]["initial"]["position"] = {6.0 * 7 + 1.0, 6.0 * 6 + 2.0, 0};
  const Scenario s = parseScenario(d);
  try {
    buildScene(s);
    FAIL() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_TRUE(hasIssue(e.issues(), "/vehicles/63/initial/position", "overlaps vehicle"));
  }
}

}  // namespace
}  // namespace groundsim::scenario::test
