// The model budget: counts of a validated scenario from its specs, checked
// against the limits before buildScene runs. The counts mirror the vehicle
// builders (physics/build/vehicle.cpp); budget_test.cpp holds them to the models
// actually built.
#include <algorithm>
#include <cmath>

#include "physics/integrators/integrator.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/scenario.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::scenario {
namespace {

struct Counts {
  long long bodies = 0, points = 0, build_points = 0, particles = 0, springs = 0, contacts = 0;
  long long aux = 0;  // states after the bodies and particles (road cars)
  void add(const Counts& o) {
    bodies += o.bodies, points += o.points, build_points += o.build_points, particles += o.particles,
        springs += o.springs, contacts += o.contacts, aux += o.aux;
  }
};

// One vehicle. build_points also counts the rim points a continuous wheel
// keeps for its inertia only: the builder handles them, the model drops them.
Counts vehicleCounts(const VehicleSpec& v) {
  const CarParams& p = v.params;
  const long long n = p.rim_points;
  const bool rim_contact = p.wheel_contact == WheelContact::RimPoints;
  Counts c;
  if (v.road_car) {
    // physics/build/road_car_builder.cpp: one body of six mass points (none in
    // contact: the tyres touch the ground analytically), no springs, and
    // kRoadCarStates states for its wheels
    c.bodies = 1;
    c.points = c.build_points = 6;
    c.aux = kRoadCarStates;
    return c;
  }
  if (v.lone_wheel) {
    c.bodies = 1;
    c.points = rim_contact ? n : 0;
    c.build_points = n;
    c.contacts = c.points;
    return c;
  }
  // the body: 8 axle points
  c.bodies = 1;
  c.points = c.build_points = 8;
  c.contacts = p.body_contact ? 8 : 0;
  for (int w = 0; w < 4; ++w) {
    Counts wh;
    wh.bodies = 1;
    if (p.deformable) {
      // hub: two rings of n and 2 bearing points; rim: n particles; springs:
      // 4 spokes and 2 tread springs per rim point, 2 bearing springs
      wh.points = wh.build_points = 2 * n + 2 + n;
      wh.particles = n;
      wh.contacts = n;
      wh.springs = 6 * n + 2;
    } else {
      const bool bearing = p.coupling == WheelCoupling::Bearing;
      const bool rim_kept = rim_contact || !bearing;
      wh.points = (rim_kept ? n : 0) + (bearing ? 2 : 0);
      wh.build_points = n + (bearing ? 2 : 0);
      wh.contacts = rim_contact ? n : 0;
      wh.springs = bearing ? 2 : 2 * n;
    }
    c.add(wh);
  }
  return c;
}

// Derivative evaluations per integrator step (implicit_euler: one per
// state component for its finite-difference Jacobian, plus one).
double evaluationsPerStep(IntegratorKind k, long long state) {
  switch (k) {
    case IntegratorKind::SemiImplicitEuler:
    case IntegratorKind::VelocityVerlet: return 1.0;
    case IntegratorKind::Rk4: return 4.0;
    case IntegratorKind::Adaptive: return 7.0;  // Dormand-Prince, per accepted step of dt at least
    case IntegratorKind::ImplicitEuler: return static_cast<double>(state) + 1.0;
  }
  return 1.0;
}

std::string count(double v) {
  // integers up to 2^53 exactly, larger ones in %g
  return v < 9.007199254740992e15 ? std::to_string(static_cast<long long>(v)) : formatNumber(v);
}

std::string vehiclesPath(const Scenario& s) { return s.document.contains("vehicles") ? "/vehicles" : "/vehicle"; }

// A refusal naming the largest vehicle when there are several.
void refuseCount(IssueList& issues, const Scenario& s, const std::vector<Counts>& per, long long Counts::*field,
                 long long total, long long limit, const char* what, const Budget& b, const char* flag) {
  if (total <= limit) return;
  std::string msg = "the model would have " + count(static_cast<double>(total)) + " " + what + ", at most " +
                    count(static_cast<double>(limit)) + " " + b.flag(flag);
  if (per.size() > 1) {
    size_t big = 0;
    for (size_t i = 1; i < per.size(); ++i)
      if (per[i].*field > per[big].*field) big = i;
    msg += "; the largest vehicle, /vehicles/" + std::to_string(big) + " (rim_points " +
           std::to_string(s.vehicles[big].params.rim_points) + "), has " + count(static_cast<double>(per[big].*field));
  } else if (!s.vehicles.empty()) {
    msg += " (rim_points " + std::to_string(s.vehicles[0].params.rim_points) + ")";
  }
  issues.add(vehiclesPath(s), msg);
}

double stepsOf(const Scenario& s, double duration) {
  return duration / s.options.dt * static_cast<double>(s.options.substeps);
}

void runLength(const Scenario& s, const ModelSize& m, double duration, const Budget& b, IssueList& issues) {
  if (!(duration > 0.0) || !std::isfinite(duration)) return;
  const double steps = stepsOf(s, duration);
  if (!(steps <= b.max_steps)) {
    issues.add("/duration", "duration " + formatNumber(duration) + " s / physics.dt " + formatNumber(s.options.dt) +
                                " s x " + std::to_string(s.options.substeps) + " substeps = " + count(steps) +
                                " steps, at most " + count(b.max_steps) + " " + b.flag("max-steps"));
    return;
  }
  const double work = steps * m.work_per_step;
  if (!(work <= b.max_work))
    issues.add("/duration", count(steps) + " steps of about " + count(m.work_per_step) + " work units each (" +
                                integratorName(s.options.integrator) + ", " + count(static_cast<double>(m.points)) +
                                " points, " + count(static_cast<double>(m.springs)) + " springs) = " + count(work) +
                                ", at most " + count(b.max_work) + " " + b.flag("max-work"));
}

}  // namespace

ModelSize estimateModelSize(const Scenario& s) {
  ModelSize m;
  Counts total;
  for (const VehicleSpec& v : s.vehicles) total.add(vehicleCounts(v));
  // an object with mass is a body whose surface probes are its points
  for (const ObjectEntry& o : s.objects) {
    if (!(o.spec.mass > 0.0)) continue;
    const long long probes = static_cast<long long>(
        o.spec.shape.probes(std::min(s.options.collision.probe_spacing, 0.5 * o.spec.shape.bound())).size());
    total.bodies += 1;
    total.points += probes;
    total.contacts += probes;
  }
  m.vehicles = static_cast<long long>(s.vehicles.size());
  m.bodies = total.bodies;
  m.points = total.points;
  m.particles = total.particles;
  m.springs = total.springs;
  m.contact_points = total.contacts;
  m.state = 13 * total.bodies + 6 * total.particles + total.aux;
  m.steps = stepsOf(s, s.duration);
  // one evaluation touches every point, spring and contact point once; the
  // stick-slip friction sweeps (up to friction_iterations, stopping once
  // converged, usually after a few) are not counted
  // (a road car's four tyres and struts are counted as its aux states)
  const double per_eval = static_cast<double>(total.points + total.springs + total.contacts + total.aux);
  m.work_per_step = evaluationsPerStep(s.options.integrator, m.state) * per_eval;
  if (s.options.integrator == IntegratorKind::ImplicitEuler) m.work_per_step += std::pow(static_cast<double>(m.state), 3) / 3.0;
  return m;
}

void checkBudget(const Scenario& s, const Budget& b) {
  IssueList issues;
  if (static_cast<long long>(s.vehicles.size()) > b.max_vehicles)
    issues.add(vehiclesPath(s), std::to_string(s.vehicles.size()) + " vehicles, at most " +
                                    std::to_string(b.max_vehicles) + " " + b.flag("max-vehicles"));
  std::vector<Counts> per;
  Counts total;
  for (const VehicleSpec& v : s.vehicles) {
    per.push_back(vehicleCounts(v));
    total.add(per.back());
  }
  refuseCount(issues, s, per, &Counts::build_points, total.build_points, b.max_points, "points", b, "max-points");
  refuseCount(issues, s, per, &Counts::springs, total.springs, b.max_springs, "springs", b, "max-springs");
  refuseCount(issues, s, per, &Counts::particles, total.particles, b.max_particles, "particles", b, "max-particles");
  const ModelSize m = estimateModelSize(s);
  if (m.state > b.max_state)
    issues.add(vehiclesPath(s), "the state would have " + count(static_cast<double>(m.state)) + " numbers (13 per body, " +
                                    "6 per particle, 20 per road car), at most " + count(static_cast<double>(b.max_state)) + " " +
                                    b.flag("max-state"));
  if (s.options.integrator == IntegratorKind::ImplicitEuler && m.state > b.max_implicit_state) {
    const double bytes = 3.0 * 8.0 * static_cast<double>(m.state) * static_cast<double>(m.state);
    issues.add("/physics/integrator", "\"implicit_euler\" factors a dense " + count(static_cast<double>(m.state)) +
                                          " x " + count(static_cast<double>(m.state)) + " matrix every step (" +
                                          formatNumber(bytes / 1e9) + " GB for its 3 matrices); state size at most " +
                                          count(static_cast<double>(b.max_implicit_state)) + " " +
                                          b.flag("max-implicit-state") + ": choose another integrator or fewer points");
  }
  // the run length only for a model within the budget: its work estimate
  // means little otherwise
  if (issues.empty()) runLength(s, m, s.duration, b, issues);
  issues.throwIfAny();
}

void checkRunLength(const Scenario& s, double duration, const Budget& b) {
  IssueList issues;
  runLength(s, estimateModelSize(s), duration, b, issues);
  issues.throwIfAny();
}

}  // namespace groundsim::scenario
