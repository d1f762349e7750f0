// Helpers of the task context (env.hpp's makeTaskContext), shared with the
// server side: the scenario hash snapshots must match, the buffers' layout,
// and a drawn parameter as an override.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "experiments/batch_env.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::experiments {

// Hex digest (two FNV-1a 64 lanes) of the validated document, task included.
std::string scenarioHash(const nlohmann::json& document);
// The buffers' layout of a validated scenario with a task (num_envs 0).
Layout makeLayout(const scenario::Scenario& s, const scenario::Scene& scene);
// "path=value", the value in 17 significant digits (%.17g: reads back exactly).
std::string overrideText(const std::string& path, double value);

}  // namespace groundsim::experiments
