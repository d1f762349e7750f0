// Trained drivers' policy files (server/drivers/policy.*): a layer's
// output against its closed form, malformed files refused naming the field,
// and the policy driver sensing a car exactly as the task's environment
// observed it, bit for bit, step after step (so a bot in a session meets
// the inputs its policy was trained on).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "drivers/policy_driver.hpp"
#include "experiments/env.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::drivers {
namespace {

// A policy of one linear layer (no activation) on `obs` inputs.
nlohmann::json linearPolicy(int obs, const std::vector<std::vector<double>>& w, const std::vector<double>& b) {
  return {{"format", "groundsim.policy"},
          {"version", 1},
          {"task", "test"},
          {"observation", {"speed"}},
          {"track_ahead", nlohmann::json::array()},
          {"control_period", 10},
          {"dt", 0.004},
          {"normalise", {{"mean", std::vector<double>(static_cast<size_t>(obs), 1.0)},
                         {"var", std::vector<double>(static_cast<size_t>(obs), 4.0)},
                         {"clip", 10.0}}},
          {"layers", {{{"weight", w}, {"bias", b}, {"activation", "none"}}}},
          {"action_low", {0.0, 0.0, -1.0}},
          {"action_high", {1.0, 1.0, 1.0}}};
}

TEST(Policy, ALinearLayerMapsTheNormalisedObservationOntoTheBounds) {
  const Policy p = Policy::parse(linearPolicy(1, {{0.5}, {-0.25}, {1.0}}, {0.0, 0.1, -0.2}).dump());
  const float obs[1] = {3.0f};  // normalised: (3 - 1) / sqrt(4 + 1e-8) = 1
  float a[3];
  p.act(obs, a);
  // u = W x + b = (0.5, -0.15, 0.8); action = mid + half u
  EXPECT_NEAR(a[0], 0.5 + 0.5 * 0.5, 1e-6);
  EXPECT_NEAR(a[1], 0.5 - 0.5 * 0.15, 1e-6);
  EXPECT_NEAR(a[2], 0.8, 1e-6);
  const float far[1] = {1e6f};  // clipped to 10 standard deviations, then to the bounds
  p.act(far, a);
  EXPECT_EQ(a[0], 1.0f);
  EXPECT_EQ(a[1], 0.0f);
  EXPECT_EQ(a[2], 1.0f);
}

TEST(Policy, MalformedFilesAreRefusedNamingTheField) {
  auto refused = [](nlohmann::json j, const std::string& field) {
    try {
      Policy::parse(j.dump());
      ADD_FAILURE() << "accepted; expected a refusal at " << field;
    } catch (const PolicyError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  const nlohmann::json good = linearPolicy(1, {{0.5}, {-0.25}, {1.0}}, {0.0, 0.1, -0.2});
  EXPECT_NO_THROW(Policy::parse(good.dump()));
  nlohmann::json j = good;
  j.erase("layers");
  refused(j, "layers: missing");
  j = good;
  j["format"] = "onnx";
  refused(j, "format");
  j = good;
  j["layers"][0]["weight"][1] = {0.1, 0.2};  // 2 inputs where the layer has 1
  refused(j, "layers/0/weight/1");
  j = good;
  j["layers"][0]["bias"] = {0.0, 0.1};
  refused(j, "layers/0/bias");
  j = good;
  j["normalise"]["var"] = {-1.0};
  refused(j, "normalise/var/0");
  j = good;
  j["dt"] = 0.0;
  refused(j, "dt");
  j = good;
  j["action_high"] = {1.0, 0.0, 1.0};
  refused(j, "action_high/1");
  try {
    Policy::parse(std::string(20000, '['));
    ADD_FAILURE() << "a deep document was parsed";
  } catch (const PolicyError& e) {
    EXPECT_NE(std::string(e.what()).find("deep"), std::string::npos) << e.what();
  }
  // NaN is not JSON: a file with one is not a document
  EXPECT_THROW(Policy::parse(R"({"format": NaN})"), PolicyError);
}

TEST(PolicyDriver, RefusesFeaturesACarInASessionCannotSense) {
  nlohmann::json j = linearPolicy(2, {{0.5, 0.0}, {0.0, 0.0}, {0.0, 0.0}}, {0.0, 0.0, 0.0});
  j["observation"] = {"goal_distance", "speed"};
  scenario::RaceSpec race;
  race.centerline = {{0.0, 0.0}, {10.0, 0.0}, {20.0, 1.0}};
  race.gates = {{{0.0, 5.0}, {0.0, -5.0}}, {{20.0, 5.0}, {20.0, -5.0}}};
  try {
    PolicyDriver d(std::make_shared<const Policy>(Policy::parse(j.dump())), std::make_shared<const TrackCourse>(race), 0);
    FAIL() << "a policy observing its goal was accepted";
  } catch (const PolicyError& e) {
    EXPECT_NE(std::string(e.what()).find("observation/0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("goal_distance"), std::string::npos) << e.what();
  }
}

// A random 2-layer policy over the task's own observation.
nlohmann::json randomPolicy(const scenario::TaskSpec& t, int obs, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 0.3);
  auto matrix = [&](int rows, int cols) {
    std::vector<std::vector<double>> m(static_cast<size_t>(rows), std::vector<double>(static_cast<size_t>(cols)));
    for (auto& r : m)
      for (double& x : r) x = n(rng);
    return m;
  };
  nlohmann::json j = linearPolicy(obs, matrix(3, obs), {0.3, -0.5, 0.0});
  j["layers"] = {{{"weight", matrix(16, obs)}, {"bias", std::vector<double>(16, 0.1)}, {"activation", "tanh"}},
                 {{"weight", matrix(3, 16)}, {"bias", {0.4, -0.6, 0.0}}, {"activation", "none"}}};
  nlohmann::json names = nlohmann::json::array();
  for (scenario::Feature f : t.observation) names.push_back(scenario::featureNames()[static_cast<size_t>(f)]);
  j["observation"] = names;
  j["track_ahead"] = t.track_ahead;
  j["normalise"]["mean"] = std::vector<double>(static_cast<size_t>(obs), 0.0);
  j["normalise"]["var"] = std::vector<double>(static_cast<size_t>(obs), 25.0);
  return j;
}

TEST(PolicyDriver, SensesItsCarAsTheTaskObservedItBitForBit) {
  const std::string path = std::string(GROUNDSIM_CONFIGS) + "/tasks/circuit_drive.json";
  const scenario::Budget budget;
  const auto files = scenario::FileAccess::local(std::string(GROUNDSIM_CONFIGS) + "/tasks");
  auto ctx = experiments::makeTaskContext(
      scenario::parseScenario(scenario::loadScenarioDocument(path, budget), budget, files), budget, files);
  const int obs_size = ctx->layout.obsSize();
  auto policy = std::make_shared<const Policy>(Policy::parse(randomPolicy(ctx->task(), obs_size, 7).dump()));
  experiments::Env env(ctx, 3);
  std::vector<float> obs(static_cast<size_t>(obs_size));
  double reward = 0.0;
  std::uint8_t term = 0, trunc = 0;
  for (std::uint64_t seed : {21u, 22u}) {  // two episodes from drawn starts along the track
    env.reset(seed, obs.data());
    PolicyDriver driver(policy, ctx->track, ctx->agents[0].body);
    int compared = 0;
    for (int k = 0; k < 150 && !term && !trunc; ++k) {
      const Simulator& sim = env.simulator();
      const std::vector<float>& sensed = driver.observe(sim.model(), sim.state());
      ASSERT_EQ(sensed.size(), obs.size());
      for (size_t i = 0; i < obs.size(); ++i)
        ASSERT_EQ(sensed[i], obs[i]) << "step " << k << ", " << ctx->layout.observation[i];
      const Pedals p = driver.drive(sim.model(), sim.state());
      const float a[3] = {static_cast<float>(p.throttle), static_cast<float>(p.brake), static_cast<float>(p.steer)};
      env.setAction(a);
      env.step(obs.data(), &reward, &term, &trunc);
      ++compared;
    }
    EXPECT_GT(compared, 20);
    term = trunc = 0;
  }
}

}  // namespace
}  // namespace groundsim::drivers
