// The scenes of the tolerance sweep (docs/accuracy.md, "Accuracy on
// demand"): the report's four experiments, the sedan's manoeuvres, a crash,
// a lone wheel, deformable tyres, a heightfield, an expression ground and
// eight cars, each a shipped config with overrides (shorter durations keep
// the converged references affordable).
#pragma once

#include <string>
#include <vector>

#include "scenario/scenario.hpp"

namespace groundsim::bench {

struct ToleranceScene {
  std::string name;
  std::string config;                  // under configs/
  std::vector<std::string> overrides;  // key.path=value, as `groundsim run --set`
};

const std::vector<ToleranceScene>& toleranceScenes();

// The scene's config with its overrides, without its own `accuracy`
// section (configs: the configs directory).
scenario::Scenario loadToleranceScene(const std::string& configs, const ToleranceScene& sc);

}  // namespace groundsim::bench
