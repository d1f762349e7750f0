#include "accuracy/model_options.hpp"

#include <algorithm>
#include <optional>

#include "physics/integrators/integrator.hpp"

namespace groundsim::accuracy {
namespace {

// The document's entry of vehicle i: `vehicle` (one) or `vehicles[i]`,
// which the Scenario keeps in document order.
nlohmann::json* vehicleDocument(scenario::Scenario& s, size_t i) {
  if (s.document.contains("vehicles") && s.document["vehicles"].is_array() && i < s.document["vehicles"].size())
    return &s.document["vehicles"][i];
  if (i == 0 && s.document.contains("vehicle") && s.document["vehicle"].is_object()) return &s.document["vehicle"];
  return nullptr;
}

std::string wheelModelName(const CarParams& p) {
  if (p.deformable) return std::to_string(p.rim_points) + "-point deformable tyres";
  if (p.wheel_contact == WheelContact::Circle) return "circle";
  return std::to_string(p.rim_points) + "-point rims on " +
         (p.coupling == WheelCoupling::Bearing ? std::string("a bearing") : std::string("rim springs"));
}

void addLine(std::string& what, const std::string& line) { what += (what.empty() ? "" : "; ") + line; }

// Rim points (either coupling) and deformable tyres -> the continuous wheel
// on a bearing: the contact of the circle the rim approximates, one contact
// per wheel instead of one per rim point, and no rim springs (the stiffest
// mode of the report's car, 2.8e-4 s at 1e5 N/m, against the bearing's).
std::optional<ModelOption> circleWheels(const scenario::Scenario& s) {
  ModelOption o{"circle wheels", "", s};
  for (size_t i = 0; i < s.vehicles.size(); ++i) {
    const scenario::VehicleSpec& v = s.vehicles[i];
    if (v.road_car || (v.params.wheel_contact == WheelContact::Circle && !v.params.deformable)) continue;
    scenario::VehicleSpec& w = o.scenario.vehicles[i];
    w.params.wheel_contact = WheelContact::Circle;
    w.params.deformable = false;
    w.params.coupling = WheelCoupling::Bearing;
    if (nlohmann::json* d = vehicleDocument(o.scenario, i)) {
      (*d)["wheel_model"] = "circle";
      (*d)["coupling"] = "bearing";
    }
    addLine(o.what, v.name + ": " + wheelModelName(v.params) + " -> circle on a bearing (" +
                        std::to_string(static_cast<long long>(v.params.bearing_stiffness)) + " N/m)");
  }
  if (o.what.empty()) return std::nullopt;
  return o;
}

// A road car's tyres: each axle's Magic Formula for the stick-slip contact
// and back, in every road car (the two differ in kind: the stick-slip tyre
// has no slip angle, so the pilot's measured gap decides).
std::optional<ModelOption> otherTyres(const scenario::Scenario& s) {
  ModelOption o{"", "", s};
  for (size_t i = 0; i < s.vehicles.size(); ++i) {
    const scenario::VehicleSpec& v = s.vehicles[i];
    if (!v.road_car) continue;
    scenario::VehicleSpec& w = o.scenario.vehicles[i];
    nlohmann::json* d = vehicleDocument(o.scenario, i);
    std::string axles;
    for (int a = 0; a < 2; ++a) {
      TyreParams& t = w.road.tyre[static_cast<size_t>(a)];
      t.slip_model = !t.slip_model;
      const char* axle = a == 0 ? "front" : "rear";
      if (d) (*d)["tyres"][axle]["model"] = t.slip_model ? "magic_formula" : "stick_slip";
      axles += std::string(a ? ", " : "") + axle + " " + (t.slip_model ? "stick-slip -> Magic Formula" : "Magic Formula -> stick-slip");
    }
    addLine(o.what, v.name + ": " + axles);
  }
  if (o.what.empty()) return std::nullopt;
  // named for what the first road car's front tyres become
  for (const scenario::VehicleSpec& w : o.scenario.vehicles)
    if (w.road_car) {
      o.name = w.road.tyre[0].slip_model ? "Magic Formula tyres" : "stick-slip tyres";
      break;
    }
  return o;
}

// The ground's friction as regularised Coulomb (mu N tanh(|u| / v_s))
// instead of the velocity-level stick-slip solve or the report's sign law:
// the law RK4 and the adaptive integrator take (their stages need forces
// that do not depend on the step). Only those two are piloted on it beyond
// the run that bounds its gap: for semi-implicit Euler and Verlet the
// scene's own law is at hand. A road car's tyres do not use the ground's
// friction, so where only its body could touch the ground the two laws'
// converged solutions coincide and the gap is the runs' own errors.
std::optional<ModelOption> regularizedFriction(const scenario::Scenario& s) {
  const FrictionModel was = s.options.contact.friction_model;
  if (was == FrictionModel::Regularized) return std::nullopt;
  ModelOption o{"regularized friction", "", s};
  o.scenario.options.contact.friction_model = FrictionModel::Regularized;
  o.scenario.document["contact"]["friction_model"] = "regularized";
  o.what = std::string("ground friction: ") + (was == FrictionModel::Sign ? "sign" : "stick-slip") +
           " -> regularized (v_s " + std::to_string(s.options.contact.slip_velocity).substr(0, 6) + " m/s)";
  o.only = {IntegratorKind::Rk4, IntegratorKind::Adaptive};
  return o;
}

}  // namespace

std::vector<ModelOption> modelOptions(const scenario::Scenario& s, bool regularized_friction) {
  std::vector<ModelOption> out;
  if (auto o = circleWheels(s)) out.push_back(std::move(*o));
  if (auto o = otherTyres(s)) out.push_back(std::move(*o));
  if (regularized_friction)
    if (auto o = regularizedFriction(s)) out.push_back(std::move(*o));
  return out;
}

double workPerEvaluation(const scenario::Scenario& s) {
  scenario::Scenario one = s;
  one.options.integrator = IntegratorKind::SemiImplicitEuler;  // one evaluation a step
  return std::max(1.0, scenario::estimateModelSize(one).work_per_step);
}

}  // namespace groundsim::accuracy
