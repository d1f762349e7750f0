// A run of a scene reduced to what the error measure needs: each vehicle's
// body-centre position at fixed sample times, its final velocity and the
// distance it travelled, plus what the run cost. Two runs of the same scene
// at different steps sample at the same times, so they compare point by
// point (error_measure.hpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "physics/base/math.hpp"
#include "physics/core/model.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::accuracy {

// Samples every kSamplePeriod of simulated time: a whole number of steps of
// every step on the ladder (settings.hpp), 0.02 s / 2^k.
inline constexpr double kSamplePeriod = 0.04;

struct Trajectory {
  std::vector<std::vector<Vec3>> positions;  // [sample][vehicle]
  std::vector<Vec3> final_velocity;          // per vehicle
  double duration = 0.0;                     // simulated, s
  bool healthy = true;
  std::string failure;                       // why it diverged, at what time
  long long steps = 0;
  long long evaluations = 0;                 // force evaluations
  double wall_seconds = 0.0;
  // the live estimate's windows alone at the end (live_estimate.hpp), when
  // the run was watched; -1 otherwise
  double windows = -1.0;
  // wall seconds per simulated second
  double cost() const { return duration > 0.0 ? wall_seconds / duration : 0.0; }
};

// A copy of s stepped with integrator `kind` at dt (one substep), contact
// with at least contact_substeps (collisions.min_substeps), its document
// saying so; `local_tolerance` > 0: the adaptive integrator's
// (physics.tolerance), its internal steps covering each dt.
scenario::Scenario withSettings(const scenario::Scenario& s, IntegratorKind kind, double dt, int contact_substeps = 1,
                                double local_tolerance = 0.0);

// Runs s (its scene built here; ScenarioError when it cannot be) for
// `duration` simulated seconds with the scene's scripted controls. With
// watch_order > 0 the live estimate watches it (its windows placed as in a
// run of s.duration, Richardson at that order) and `windows` is its reading
// at the end; the run itself is the same, bit for bit.
Trajectory runTrajectory(const scenario::Scenario& s, double duration, int watch_order = 0);

// The sampling loop under runTrajectory: `sim` (of `scene`) run for
// `duration`, `advance(n)` taking each chunk of n steps between samples
// (false: diverged, the run ends there), which may watch or refine it
// (refinement.hpp's runRefined).
Trajectory sampleRun(const scenario::Scene& scene, Simulator& sim, double duration,
                     const std::function<bool(long long)>& advance);

}  // namespace groundsim::accuracy
