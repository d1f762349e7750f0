#include "accuracy/trajectory.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "accuracy/live_estimate.hpp"
#include "physics/checks/telemetry.hpp"
#include "physics/integrators/integrator.hpp"
#include "physics/simulator.hpp"

namespace groundsim::accuracy {

scenario::Scenario withSettings(const scenario::Scenario& s, IntegratorKind kind, double dt, int contact_substeps,
                                double local_tolerance) {
  scenario::Scenario c = s;
  c.options.integrator = kind;
  c.options.dt = dt;
  c.options.substeps = 1;
  nlohmann::json& physics = c.document["physics"];
  physics["integrator"] = integratorName(kind);
  physics["dt"] = dt;
  physics["substeps"] = 1;
  if (local_tolerance > 0.0) {
    c.options.tolerance = local_tolerance;
    physics["tolerance"] = local_tolerance;
  }
  c.options.collision.min_substeps = contact_substeps;
  if (contact_substeps > 1) c.document["collisions"]["min_substeps"] = contact_substeps;
  else if (c.document.contains("collisions") && c.document["collisions"].is_object())
    c.document["collisions"]["min_substeps"] = 1;
  return c;
}

namespace {

void sample(const Simulator& sim, const scenario::Scene& scene, std::vector<Vec3>& positions,
            std::vector<Vec3>* velocities) {
  positions.clear();
  if (velocities) velocities->clear();
  for (const CarHandle& car : scene.cars) {
    const VehicleSample v = sampleVehicle(sim, car.vehicle, false);
    positions.push_back(v.position);
    if (velocities) velocities->push_back(v.velocity);
  }
}

}  // namespace

Trajectory sampleRun(const scenario::Scene& scene, Simulator& sim, double duration,
                     const std::function<bool(long long)>& advance) {
  const double dt = sim.model().opt.dt;
  const long long total = std::max(1LL, std::llround(duration / dt));
  const long long per_sample = std::max(1LL, std::llround(kSamplePeriod / dt));
  Trajectory t;
  t.duration = static_cast<double>(total) * dt;
  t.positions.emplace_back();
  sample(sim, scene, t.positions.back(), nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  long long done = 0;
  while (done < total) {
    const long long n = std::min(per_sample - done % per_sample, total - done);
    if (!advance(n)) break;
    done += n;
    t.positions.emplace_back();
    sample(sim, scene, t.positions.back(), done == total ? &t.final_velocity : nullptr);
  }
  t.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t.steps = sim.state().tick;
  t.evaluations = sim.forceEvaluations();
  if (!sim.healthy()) {
    t.healthy = false;
    char buf[64];
    std::snprintf(buf, sizeof buf, " at t = %.4g s", sim.state().t);
    t.failure = std::string(healthName(sim.state().health)) + buf + ": " + sim.state().health_reason;
  }
  return t;
}

Trajectory runTrajectory(const scenario::Scenario& s, double duration, int watch_order) {
  const scenario::Scene scene = scenario::buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  std::unique_ptr<LiveEstimate> live;
  if (watch_order > 0) {
    LiveEstimateOptions o;
    o.duration = s.duration;
    live = std::make_unique<LiveEstimate>(s, watch_order, o);
  }
  Trajectory t = sampleRun(
      scene, sim, duration, [&](long long n) { return stepWatched(scene, sim, n, live.get()); });
  if (live) {
    live->beforeStep(sim);  // a last update at the end
    t.windows = std::max(live->pathEstimate(), live->speedEstimate());
  }
  return t;
}

}  // namespace groundsim::accuracy
