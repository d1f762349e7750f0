#include "scenario/presets.hpp"

namespace groundsim::scenario {

const std::vector<std::string>& presetNames() {
  static const std::vector<std::string> names = {"fast", "balanced", "accurate"};
  return names;
}

nlohmann::json presetSettings(const std::string& name) {
  // All three roll a continuous wheel (exact circle contact) on a bearing of
  // two zero-length springs: the 20-point rim of the report rolls like a
  // polygon and misses the analytic answers by 5-40% whatever the step.
  // The bearing springs set the stiffest mode (wheel against body), so each
  // preset pairs a bearing stiffness with the step that keeps omega*dt ~ 1
  // (symplectic Euler is stable below 2, less with damping).
  // fast: 5e3 N/m at dt 2.5 ms (the wheel sits 0.25 mm lower in its
  // bearing); omega*dt 0.87 leaves room for a damped ground, whose damping
  // lowers the limit (ground 20 N s/m: limit 1.1)
  if (name == "fast")
    return {{"physics", {{"integrator", "semi_implicit_euler"}, {"dt", 2.5e-3}}},
            {"vehicle", {{"wheel_model", "circle"}, {"coupling", "bearing"},
                         {"bearing_stiffness", 5e3}, {"bearing_damping", 10.0}}}};
  // balanced: 5e4 N/m at dt 1 ms.
  if (name == "balanced")
    return {{"physics", {{"integrator", "semi_implicit_euler"}, {"dt", 1e-3}}},
            {"vehicle", {{"wheel_model", "circle"}, {"coupling", "bearing"},
                         {"bearing_stiffness", 5e4}, {"bearing_damping", 20.0}}}};
  // accurate: second-order velocity Verlet, 1e5 N/m at dt 0.25 ms.
  if (name == "accurate")
    return {{"physics", {{"integrator", "velocity_verlet"}, {"dt", 2.5e-4}}},
            {"vehicle", {{"wheel_model", "circle"}, {"coupling", "bearing"},
                         {"bearing_stiffness", 1e5}, {"bearing_damping", 20.0}}}};
  return nullptr;
}

namespace {

void fill(nlohmann::json& target, const nlohmann::json& values, bool force) {
  if (!target.is_object()) return;  // validation will name the wrong type
  for (const auto& [key, value] : values.items())
    if (force || !target.contains(key)) target[key] = value;
}

}  // namespace

void applyPreset(nlohmann::json& doc, bool force) {
  if (!doc.is_object() || !doc.contains("preset") || !doc["preset"].is_string()) return;
  const nlohmann::json p = presetSettings(doc["preset"].get<std::string>());
  if (p.is_null()) return;
  if (!doc.contains("physics")) doc["physics"] = nlohmann::json::object();
  fill(doc["physics"], p["physics"], force);
  if (doc.contains("vehicle")) fill(doc["vehicle"], p["vehicle"], force);
  if (doc.contains("vehicles") && doc["vehicles"].is_array())
    for (auto& v : doc["vehicles"]) fill(v, p["vehicle"], force);
}

}  // namespace groundsim::scenario
