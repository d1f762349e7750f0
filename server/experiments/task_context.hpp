// Helpers of the task context (env.hpp's makeTaskContext), shared with the
// server side: the scenario hash snapshots must match, the buffers' layout,
// and a drawn parameter as an override.
#pragma once

#include <string>
#include <vector>

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

struct TaskContext;
// Throws ScenarioError (at `pointer`/i/range) unless both ends of every
// parameter range validate with the context's scenario, so that a reset
// never meets a document the scenario layer refuses.
void checkParameterEnds(const TaskContext& ctx, const std::vector<scenario::ParameterRange>& ranges,
                        const std::string& pointer);
// A curriculum (the task's `randomize` schema as JSON text, every key
// optional): the ranges that replace `current` at the next resets. Throws
// ScenarioError naming the field (/randomize/...).
// check_ends: validate the ends of the parameter ranges that differ from
// `current` (each costs two scenario parses). Every range an env holds was
// validated when it was set, so a caller applying one curriculum to many
// envs checks the ends once, against the first env, and not again.
scenario::Randomization curriculumRanges(const TaskContext& ctx, const std::string& randomize_json,
                                         const scenario::Randomization& current, bool check_ends = true);
// Ranges as the task's `randomize` JSON, and back (snapshots carry them).
nlohmann::json rangesJson(const scenario::Randomization& r);

}  // namespace groundsim::experiments
