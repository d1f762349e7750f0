// Named speed/accuracy trade-offs. A preset fills the settings it names
// (integrator, step, wheel model and coupling) wherever the scenario leaves
// them out; keys the scenario gives explicitly win. On the command line
// (`groundsim run --preset`) it replaces those keys instead, since the user
// asked for it over the file. Figures behind each choice: docs/accuracy.md.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace groundsim::scenario {

const std::vector<std::string>& presetNames();

// The settings a preset stands for, as a partial scenario document
// ({"physics": {...}, "vehicle": {...}}), or null for an unknown name.
nlohmann::json presetSettings(const std::string& name);

// The settings a preset stands for on a scenario whose vehicles are all road
// cars ({"physics": {...}} and, for an ODE integrator, {"contact":
// {"friction_model": "regularized"}}), or null for an unknown name.
nlohmann::json roadCarPresetSettings(const std::string& name);

// Fills doc's missing keys from doc["preset"] (no-op without a valid
// preset; validation reports a bad one). With force, the preset's keys are
// overwritten too.
void applyPreset(nlohmann::json& doc, bool force = false);

}  // namespace groundsim::scenario
