// Helpers of the experiments tests: small task documents and a batch with
// its buffers, read by feature name.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/vec_env.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::experiments::test {

// A road car (the default sedan-like parameters) on `ground`, with `task`.
inline nlohmann::json roadCarDoc(nlohmann::json ground, nlohmann::json task, nlohmann::json initial = nlohmann::json::object()) {
  return {{"physics", {{"dt", 0.004}}},
          {"contact", {{"friction", 1.0}}},
          {"ground", std::move(ground)},
          {"vehicle", {{"name", "sedan"}, {"kind", "road_car"}, {"initial", std::move(initial)}}},
          {"task", std::move(task)}};
}

// The report's car with the fast preset.
inline nlohmann::json reportCarDoc(nlohmann::json ground, nlohmann::json task, nlohmann::json initial = nlohmann::json::object()) {
  return {{"preset", "fast"},
          {"contact", {{"stiffness", 2000}, {"damping", 20}, {"friction", 0.9}}},
          {"ground", std::move(ground)},
          {"vehicle", {{"name", "car"}, {"initial", std::move(initial)}}},
          {"task", std::move(task)}};
}

inline nlohmann::json plane() { return {{"type", "plane"}}; }

inline std::string configPath(const std::string& name) {
  return std::string(GROUNDSIM_SOURCE_DIR) + "/configs/tasks/" + name;
}

struct Batch {
  std::unique_ptr<BatchEnv> env;
  int n = 0;
  std::vector<float> obs, act;
  std::vector<double> rew;
  std::vector<std::uint8_t> term, trunc;

  explicit Batch(std::unique_ptr<BatchEnv> e) : env(std::move(e)) {
    const Layout& l = env->layout();
    n = l.rows();  // one row per agent of each environment
    obs.assign(static_cast<size_t>(n * l.obsSize()), 0.0f);
    act.assign(static_cast<size_t>(n * l.actionSize()), 0.0f);
    rew.assign(static_cast<size_t>(n), 0.0);
    term.assign(static_cast<size_t>(n), 0);
    trunc.assign(static_cast<size_t>(n), 0);
  }
  Batch(const nlohmann::json& doc, int num_envs, int threads = 1)
      : Batch(makeVecEnv(doc.dump(), num_envs, {.num_threads = threads})) {}
  const Layout& layout() const { return env->layout(); }
  void reset(std::optional<std::uint64_t> seed = 0) { env->reset(seed, obs.data()); }
  void step() { env->step(act.data(), obs.data(), rew.data(), term.data(), trunc.data()); }
  int index(const std::string& name) const {
    const auto& names = layout().observation;
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return static_cast<int>(i);
    ADD_FAILURE() << "no observation component " << name;
    return 0;
  }
  double o(const std::string& name, int e = 0) const {
    return obs[static_cast<size_t>(e * layout().obsSize() + index(name))];
  }
  float* a(int e = 0) { return act.data() + static_cast<size_t>(e * layout().actionSize()); }
  // the same action for every environment; it must be one whole action
  void setAll(std::vector<float> values) {
    if (values.size() != static_cast<size_t>(layout().actionSize())) {
      ADD_FAILURE() << values.size() << " action values for an action of " << layout().actionSize();
      return;
    }
    for (int e = 0; e < n; ++e)
      for (size_t k = 0; k < values.size(); ++k) a(e)[k] = values[k];
  }
};

}  // namespace groundsim::experiments::test
