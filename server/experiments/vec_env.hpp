// In-process vectorised environments: N copies of one scenario's task,
// stepped on a thread pool. Environments share one immutable Model (one per
// set of randomised parameters) and own their State, Workspace and random
// stream, so results do not depend on the number of threads.
#pragma once

#include <memory>
#include <string>

#include "experiments/batch_env.hpp"
#include "scenario/budget.hpp"
#include "scenario/file_access.hpp"

namespace groundsim::experiments {

struct VecEnvOptions {
  int num_threads = 0;              // 0: one per core; 1: the calling thread only
  scenario::Budget budget{};        // limits of the scenario layer (per environment)
  scenario::FileAccess files = scenario::FileAccess::none();  // heightfields named by the scenario
  int max_envs = 4096;              // refused above, as /num_envs
};

// scenario_text: a scenario document with a `task` section. Throws
// scenario::ScenarioError (JSON-pointer issues) for a bad scenario or task,
// ExperimentError for bad arguments.
std::unique_ptr<BatchEnv> makeVecEnv(const std::string& scenario_text, int num_envs,
                                     const VecEnvOptions& options = {});

// A scenario file: its heightfields are read next to it (FileAccess::local).
std::unique_ptr<BatchEnv> makeVecEnvFromFile(const std::string& path, int num_envs,
                                             VecEnvOptions options = {});

}  // namespace groundsim::experiments
