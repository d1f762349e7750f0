// Scenario -> Scene: the physics model and its initial state. The document
// is valid by now; what can still fail is only visible while building (an
// integrator this build lacks, no ground below a car, overlapping cars).
#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "physics/build/collision_build.hpp"
#include "physics/build/road_car_builder.hpp"
#include "physics/checks/stability.hpp"
#include "physics/integrators/integrator.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/footprint.hpp"
#include "scenario/scenario.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::scenario {
namespace {

constexpr IntegratorKind kAllIntegrators[] = {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet,
                                              IntegratorKind::Rk4, IntegratorKind::ImplicitEuler,
                                              IntegratorKind::Adaptive};

bool available(IntegratorKind k) {
  try {
    makeIntegrator(k);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

void checkIntegrator(IntegratorKind kind, IssueList& issues) {
  if (available(kind)) return;
  std::string list;
  for (IntegratorKind k : kAllIntegrators)
    if (available(k)) {
      if (!list.empty()) list += ", ";
      list += '"';
      list += integratorName(k);
      list += '"';
    }
  std::string why = "\"";
  why += integratorName(kind);
  why += "\" is not available in this build (available: " + list + ")";
  issues.add("/physics/integrator", why);
}

std::string vehiclePath(const Scenario& s, size_t i) {
  return s.document.contains("vehicles") ? "/vehicles/" + std::to_string(i) : "/vehicle";
}

double footprint(const VehicleSpec& v) { return vehicleFootprint(v); }

// Placed on the ground, two vehicles overlap when their footprint
// rectangles do; placed freely (z separates too), when their footprint
// circles' spheres do.
bool overlap(const VehicleSpec& a, const VehicleSpec& b, double* dist) {
  const Vec3 d = b.placement.position - a.placement.position;
  const bool flat = a.placement.on_ground && b.placement.on_ground;
  *dist = flat || a.placement.on_ground || b.placement.on_ground ? std::hypot(d.x(), d.y()) : d.norm();
  if (flat) return footprintsOverlap(a, b);
  return *dist < footprint(a) + footprint(b);
}

std::string rectangle(const VehicleSpec& v) {
  const Footprint f = vehicleRectangle(v);
  return formatNumber(f.front + f.back) + " x " + formatNumber(2.0 * f.half_width) + " m";
}

// Cars placed inside each other start with huge spring and contact forces
// and diverge in the first steps: refuse them with both names. Each vehicle
// is reported once, with the first earlier vehicle it overlaps, so the
// report grows with the vehicles, not with their pairs. The candidates come
// from a grid of cells as wide as the largest footprint pair, so the check
// costs about one distance per neighbour instead of one per pair (1,000
// vehicles piled on one spot used to list 499,500 pairs).
void checkOverlaps(const Scenario& s, IssueList& issues) {
  double cell = 0.0;
  for (const VehicleSpec& v : s.vehicles) cell = std::max(cell, 2.0 * footprint(v));
  if (!(cell > 0.0)) return;
  // a footprint may be tiny (1e-300 m) while positions reach 1e9: the cells
  // are made at least 2^-50 of the farthest position, so every cell index
  // is an exact integer in a double (a larger cell costs time, never a
  // missed overlap)
  double far = 0.0;
  for (const VehicleSpec& v : s.vehicles)
    far = std::max({far, std::abs(v.placement.position.x()), std::abs(v.placement.position.y())});
  cell = std::max(cell, far * 0x1p-50);
  auto index = [&](double x) { return static_cast<long long>(std::clamp(std::floor(x / cell), -0x1p52, 0x1p52)); };
  auto cellOf = [&](const VehicleSpec& v) {
    return std::pair<long long, long long>(index(v.placement.position.x()), index(v.placement.position.y()));
  };
  std::map<std::pair<long long, long long>, std::vector<size_t>> grid;
  for (size_t j = 0; j < s.vehicles.size(); ++j) {
    const VehicleSpec& b = s.vehicles[j];
    const auto [cx, cy] = cellOf(b);
    bool found = false;
    for (long long dx = -1; dx <= 1 && !found; ++dx)
      for (long long dy = -1; dy <= 1 && !found; ++dy) {
        const auto it = grid.find({cx + dx, cy + dy});
        if (it == grid.end()) continue;
        for (size_t i : it->second) {
          double dist = 0.0;
          if (!overlap(s.vehicles[i], b, &dist)) continue;
          issues.add(vehiclePath(s, j) + "/initial/position",
                     "overlaps vehicle " + quote(s.vehicles[i].name) + ": their footprints (" +
                         rectangle(s.vehicles[i]) + " and " + rectangle(b) + ") meet, centres " +
                         formatNumber(dist) + " m apart");
          found = true;
          break;
        }
      }
    grid[{cx, cy}].push_back(j);
  }
}

// The stick-slip tyre is a velocity-level solve sized by the step, like the
// ground's stick-slip friction: only the time-stepping integrators own it.
void checkStickSlipTyres(const Scenario& s, IssueList& issues) {
  const IntegratorKind k = s.options.integrator;
  if (k == IntegratorKind::SemiImplicitEuler || k == IntegratorKind::VelocityVerlet) return;
  for (size_t i = 0; i < s.vehicles.size(); ++i) {
    const VehicleSpec& v = s.vehicles[i];
    if (!v.road_car) continue;
    const bool front = !v.road.tyre[0].slip_model, rear = !v.road.tyre[1].slip_model;
    if (!front && !rear) continue;
    const char* where = front && rear ? "/tyres/model" : front ? "/tyres/front/model" : "/tyres/rear/model";
    issues.add(vehiclePath(s, i) + where,
               std::string("\"stick_slip\" not with integrator \"") + integratorName(k) +
                   "\": its friction and brake impulses are sized by the step, which only semi_implicit_euler "
                   "and velocity_verlet own (an RK4 stage or a trial step would change them); use one of those "
                   "or \"magic_formula\"");
  }
}

void setControls(const VehicleControlSpec& c, const CarHandle& car, std::vector<WheelControl>& controls) {
  for (int k = 0; k < 4; ++k) {
    const bool driven = c.drive_wheels == DriveWheels::All || (c.drive_wheels == DriveWheels::Front && k < 2) ||
                        (c.drive_wheels == DriveWheels::Rear && k >= 2);
    if (car.wheels[k] < 0) continue;  // a lone wheel has one
    WheelControl& w = controls.at(static_cast<size_t>(car.wheels[k]));
    w.drive_torque = driven ? c.drive_torque : 0.0;
    w.brake_torque = c.brake_torque;
    w.steer = c.steer;  // only steerable (front) wheels turn
  }
}

// Objects resting on the ground take the height of the ground below them
// plus the half height of their rotated shape's box.
void addObjects(const Scenario& s, ModelBuilder& builder, IssueList& issues) {
  for (const ObjectEntry& e : s.objects) {
    ObjectSpec o = e.spec;
    if (e.on_ground) {
      Vec3 surface, normal;
      if (!groundPointBelow(*builder.model().ground, o.position.x(), o.position.y(), &surface, &normal)) {
        issues.add(e.path + "/position", "no ground surface below it");
        continue;
      }
      const Vec3 reach = o.orientation.normalized().toRotationMatrix().cwiseAbs() * o.shape.extents();
      o.position.z() = surface.z() + reach.z();
    }
    try {
      addSceneObject(builder, o);
    } catch (const std::invalid_argument& err) {
      issues.add(e.path, err.what());
    }
  }
}

}  // namespace

Scene buildScene(const Scenario& s) {
  IssueList issues;
  checkIntegrator(s.options.integrator, issues);
  if (const char* why = integratorFrictionConflict(s.options.integrator, s.options.contact.friction_model))
    issues.add("/contact/friction_model",
               std::string("not with integrator \"") + integratorName(s.options.integrator) + "\": " + why);
  checkStickSlipTyres(s, issues);
  checkOverlaps(s, issues);
  issues.throwIfAny();

  ModelBuilder builder(s.options, makeGround(s.ground));
  Scene scene;
  for (size_t i = 0; i < s.vehicles.size(); ++i) {
    const VehicleSpec& v = s.vehicles[i];
    try {
      scene.cars.push_back(v.road_car     ? addRoadCar(builder, v.name, v.road, v.placement)
                           : v.lone_wheel ? addLoneWheel(builder, v.name, v.params, v.placement)
                                          : addCar(builder, v.name, v.params, v.placement));
      if (v.road_car) scene.control_tables.push_back({static_cast<int>(scene.control_tables.size()), v.controls});
      scene.vehicle_names.push_back(v.name);
    } catch (const std::invalid_argument& e) {
      issues.add(vehiclePath(s, i), e.what());
    }
  }
  issues.throwIfAny();
  for (const CarHandle& car : scene.cars) addVehicleCollision(builder, car.vehicle);
  addObjects(s, builder, issues);
  issues.throwIfAny();
  try {
    scene.built = builder.build();
  } catch (const std::invalid_argument& e) {
    throw ScenarioError({Issue{"", std::string("cannot build the model: ") + e.what()}});
  }
  for (size_t i = 0; i < s.vehicles.size(); ++i)
    if (!s.vehicles[i].road_car) setControls(s.vehicles[i].control, scene.cars[i], scene.built.initial.controls);
  for (const ControlTable& ct : scene.control_tables)
    if (!ct.rows.empty() && ct.rows.front().t <= 0.0)
      scene.built.initial.car_controls.at(static_cast<size_t>(ct.road_car)) = ct.rows.front().controls;
  scene.duration = s.duration;
  scene.output_rate = s.output_rate;
  scene.warnings = stabilityWarnings(*scene.built.model);
  return scene;
}

}  // namespace groundsim::scenario

namespace groundsim::scenario {

const TimedControls* rowInForce(const ControlTable& table, double t, double dt) {
  const double due = t + 0.5 * dt;
  const auto after = std::upper_bound(table.rows.begin(), table.rows.end(), due,
                                      [](double x, const TimedControls& r) { return x < r.t; });
  return after == table.rows.begin() ? nullptr : &*(after - 1);
}

bool stepScene(const Scene& scene, Simulator& sim, long long n) {
  if (scene.control_tables.empty()) return sim.step(n);
  for (long long i = 0; i < n; ++i) {
    for (const ControlTable& ct : scene.control_tables)
      if (const TimedControls* row = rowInForce(ct, sim.state().t, sim.model().opt.dt))
        sim.setCarControls(ct.road_car, row->controls);
    if (!sim.step()) return false;
  }
  return true;
}

}  // namespace groundsim::scenario
