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

nlohmann::json roadCarPresetSettings(const std::string& name) {
  // Taken from the sweep of the sedan's manoeuvres (bench/accuracy, the
  // "Road-car presets" table of docs/accuracy.md, which
  // tests/vehicle/road_preset_test.cpp compares with this): the cheapest
  // setting whose path stays within the preset's bound of a converged
  // reference on every manoeuvre. substeps 1: the step is the one measured.
  const auto physics = [](const char* integrator, double dt) {
    nlohmann::json p = {{"physics", {{"integrator", integrator}, {"dt", dt}, {"substeps", 1}}}};
    // the ODE integrators are refused with the default stick-slip ground
    // friction; a road car's tyres do not use it
    const std::string i = integrator;
    if (i == "rk4" || i == "adaptive" || i == "implicit_euler") p["contact"] = {{"friction_model", "regularized"}};
    return p;
  };
  // fast (5%) and balanced (1%) coincide: the next cheaper settings, semi-
  // implicit Euler at 16 ms (diverges) and Verlet at 16 ms (8% off on the
  // step steer), miss both bounds; 8 ms stays within 0.2% everywhere.
  if (name == "fast") return physics("semi_implicit_euler", 8e-3);
  if (name == "balanced") return physics("semi_implicit_euler", 8e-3);
  // accurate (0.1%): Verlet at 8 ms, worst 0.06% (braking)
  if (name == "accurate") return physics("velocity_verlet", 8e-3);
  return nullptr;
}

namespace {

bool isRoadCar(const nlohmann::json& v) {
  return v.is_object() && v.contains("kind") && v["kind"] == "road_car";
}

void fill(nlohmann::json& target, const nlohmann::json& values, bool force) {
  if (!target.is_object()) return;  // validation will name the wrong type
  for (const auto& [key, value] : values.items())
    if (force || !target.contains(key)) target[key] = value;
}

}  // namespace

void applyPreset(nlohmann::json& doc, bool force) {
  if (!doc.is_object() || !doc.contains("preset") || !doc["preset"].is_string()) return;
  const std::string name = doc["preset"].get<std::string>();
  const nlohmann::json p = presetSettings(name);
  if (p.is_null()) return;
  // A road car takes none of the report car's wheel keys (they would be
  // refused as unknown). When every vehicle is a road car the physics comes
  // from the road-car table; with a report car among them, from the report
  // car's (its bearing stiffness is matched to that step).
  std::vector<nlohmann::json*> vehicles;
  if (doc.contains("vehicle")) vehicles.push_back(&doc["vehicle"]);
  if (doc.contains("vehicles") && doc["vehicles"].is_array())
    for (auto& v : doc["vehicles"]) vehicles.push_back(&v);
  bool all_road = !vehicles.empty();
  for (const nlohmann::json* v : vehicles) all_road = all_road && isRoadCar(*v);
  const nlohmann::json road = roadCarPresetSettings(name);
  const nlohmann::json& chosen = all_road ? road : p;
  for (const auto& [section, values] : chosen.items()) {
    if (section == "vehicle") continue;
    if (!doc.contains(section)) doc[section] = nlohmann::json::object();
    fill(doc[section], values, force);
  }
  for (nlohmann::json* v : vehicles)
    if (!isRoadCar(*v)) fill(*v, p["vehicle"], force);
}

}  // namespace groundsim::scenario
