#include "road_scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "physics/simulator.hpp"
#include "physics/integrators/integrator.hpp"
#include "physics/checks/telemetry.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::accuracy {
namespace {

using nlohmann::json;

// Control rows at multiples of 80 ms: a whole number of steps at every step
// of the grid, so a coarse step applies them at the same instant as the
// reference (else the comparison would measure the table's rounding).
json manoeuvreDoc(const std::string& name, const std::string& configs, double duration) {
  json doc = scenario::loadScenarioDocument(configs + (name == "hill_road" ? "/sedan_hills.json" : "/sedan.json"));
  json& v = doc["vehicle"];
  if (name == "step_steer") {
    // 25 m/s, steer 0.05 (1.75 deg road-wheel) from 0.8 s: about 0.4 g
    v["initial"]["speed"] = 25.0;
    v["controls"] = json::array({{{"t", 0}, {"throttle", 0.3}}, {{"t", 0.8}, {"steer", 0.05}}});
  } else if (name == "lane_change") {
    // 25 m/s: steer 0.04 left for 0.96 s, as long right, then straight
    v["initial"]["speed"] = 25.0;
    v["controls"] = json::array({{{"t", 0}, {"throttle", 0.3}},
                                 {{"t", 0.8}, {"steer", 0.04}},
                                 {{"t", 1.76}, {"steer", -0.04}},
                                 {{"t", 2.72}, {"steer", 0.0}}});
  } else if (name == "braking") {
    // full braking (ABS) from 100 km/h until the car stands
    v["initial"]["speed"] = 100.0 / 3.6;
    v["controls"] = json::array({{{"t", 0}, {"brake", 1.0}}});
  } else if (name == "bumps") {
    // 20 m/s over 5 cm egg-crate bumps (8 m along, 14 m across), both
    // wheel tracks near a crest line across: heave, pitch and some roll
    doc["ground"] = {{"type", "bumps"}, {"amplitude", 0.05}, {"wavelength_x", 8.0}, {"wavelength_y", 14.0}};
    v["initial"] = {{"position", {0.0, 3.5, 0.0}}, {"speed", 20.0}};
    v["controls"] = json::array({{{"t", 0}, {"throttle", 0.3}}});
  }
  // hill_road: configs/sedan_hills.json as shipped, its first `duration` s
  doc["duration"] = duration;
  return doc;
}

void useStickSlip(json& doc) {
  json& t = doc["vehicle"]["tyres"];
  if (t.contains("front") || t.contains("rear")) {
    t["front"]["model"] = "stick_slip";
    t["rear"]["model"] = "stick_slip";
  } else {
    t["model"] = "stick_slip";
  }
}

void applySetting(json& doc, const Setting& s) {
  doc["physics"] = {{"integrator", integratorName(s.integrator)}, {"dt", s.dt}};
  if (s.integrator == IntegratorKind::Adaptive) doc["physics"]["tolerance"] = s.tolerance;
  // the ODE integrators are refused with the (default) stick-slip ground
  // friction; a road car's tyres do not use it, so this changes nothing else
  if (s.integrator == IntegratorKind::Rk4 || s.integrator == IntegratorKind::Adaptive ||
      s.integrator == IntegratorKind::ImplicitEuler)
    doc["contact"]["friction_model"] = "regularized";
}

}  // namespace

const std::vector<RoadManoeuvre>& roadManoeuvres() {
  static const std::vector<RoadManoeuvre> all = {
      {"step_steer", "25 m/s, throttle 0.3, steer 0 -> 0.05 at 0.8 s (rate-limited), 4 s", "yaw rate at 4 s (rad/s)", 4.0},
      {"lane_change", "25 m/s, steer +0.04 for 0.96 s from 0.8 s, -0.04 for 0.96 s, then 0; 5 s", "peak yaw rate (rad/s)", 5.0},
      {"braking", "100 km/h, brake 1 (ABS) from 0 s, 4 s (stands from ~2.9 s)", "stopping distance (m)", 4.0},
      {"hill_road", "configs/sedan_hills.json, first 40 s (flat, the +5% climb, over the crest)", "speed at 40 s (m/s)", 40.0},
      {"bumps", "20 m/s, throttle 0.3, over 5 cm bumps (8 m x 14 m), 4 s", "peak suspension travel (m)", 4.0},
  };
  return all;
}

std::vector<Setting> roadSettings(bool quick) {
  std::vector<Setting> out;
  auto add = [&](IntegratorKind k, std::vector<double> dts) {
    for (double dt : dts) out.push_back({k, dt, 1e-6, Fidelity::Circle});
  };
  if (quick) {
    add(IntegratorKind::SemiImplicitEuler, {1e-3, 4e-3});
    add(IntegratorKind::Rk4, {4e-3});
    return out;
  }
  add(IntegratorKind::SemiImplicitEuler, {2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2});
  add(IntegratorKind::VelocityVerlet, {2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2});
  add(IntegratorKind::Rk4, {5e-4, 1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2});
  add(IntegratorKind::ImplicitEuler, {1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2});
  // adaptive: output step 8 ms (controls and the velocity-level brakes act per output step)
  for (double tol : {1e-3, 1e-4, 1e-5, 1e-6}) out.push_back({IntegratorKind::Adaptive, 8e-3, tol, Fidelity::Circle});
  return out;
}

std::vector<Setting> stickSlipSettings(bool quick) {
  std::vector<Setting> out;
  for (IntegratorKind k : {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet})
    for (double dt : quick ? std::vector<double>{1e-3, 4e-3}
                           : std::vector<double>{2.5e-4, 5e-4, 1e-3, 2e-3, 4e-3, 8e-3, 1.6e-2})
      out.push_back({k, dt, 1e-6, Fidelity::Circle});
  return out;
}

RoadRun runRoad(const RoadManoeuvre& m, const Setting& s, const std::string& configs, bool stick_slip) {
  RoadRun r;
  r.manoeuvre = m.name;
  r.setting = s;
  r.stick_slip = stick_slip;
  json doc = manoeuvreDoc(m.name, configs, m.duration);
  applySetting(doc, s);
  if (stick_slip) useStickSlip(doc);
  const scenario::Scene scene = scenario::buildScene(scenario::parseScenario(doc, scenario::FileAccess::local(configs)));
  Simulator sim(scene.built.model, scene.built.initial);
  const int body = sim.model().road_cars.at(0).body;
  const int base = sim.model().auxBase(), aux = sim.model().road_cars[0].aux;
  const long long per = std::llround(kRoadSample / s.dt);
  const long long samples = std::llround(m.duration / kRoadSample);
  const Vec3 p0 = bodyPos(sim.state().y, body);
  Vec3 last = p0;
  double peak = 0;
  for (long long k = 0; k < samples; ++k) {
    const long long e0 = sim.forceEvaluations();
    const double t0 = sim.state().t;
    const auto start = std::chrono::steady_clock::now();
    const bool ok = scenario::stepScene(scene, sim, per);
    r.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.evaluations += sim.forceEvaluations() - e0;
    r.sim_seconds += sim.state().t - t0;
    if (!ok) {
      r.healthy = false;
      r.status = healthName(sim.state().health);
      return r;
    }
    const Vec3 p = bodyPos(sim.state().y, body);
    r.path.push_back(p);
    r.length += (p - last).norm();
    last = p;
    if (m.name == "lane_change") peak = std::max(peak, std::abs(sampleVehicle(sim, 0, false).yaw_rate));
    if (m.name == "bumps")
      for (int w = 0; w < 4; ++w) peak = std::max(peak, std::abs(sim.state().y[base + aux + roadAux(w, 0)]));
  }
  if (m.name == "step_steer") r.key = sampleVehicle(sim, 0, false).yaw_rate;
  else if (m.name == "braking") r.key = (last - p0).norm();
  else if (m.name == "hill_road") r.key = sampleVehicle(sim, 0, false).speed;
  else r.key = peak;
  return r;
}

void compareRoad(RoadRun& r, const RoadRun& ref) {
  if (!r.healthy || !ref.healthy || ref.length <= 0) return;
  const size_t n = std::min(r.path.size(), ref.path.size());
  double sum = 0, most = 0;
  for (size_t i = 0; i < n; ++i) {
    const double d = (r.path[i] - ref.path[i]).norm();
    sum += d * d;
    most = std::max(most, d);
  }
  r.path_rms = n ? std::sqrt(sum / n) / ref.length : 0;
  r.path_max = most / ref.length;
  r.key_error = std::abs(r.key - ref.key) / std::max(std::abs(ref.key), 1e-12);
}

}  // namespace groundsim::accuracy
