// The validated `accuracy` section: the error a user accepts. When present,
// the accuracy layer (server/accuracy) chooses integrator and step from a
// pilot on the scene itself and watches the error while the run goes;
// docs/accuracy.md ("Accuracy on demand") defines the error measure.
#pragma once

namespace groundsim::scenario {

struct AccuracySpec {
  // accepted error: the larger of each vehicle's path error relative to the
  // distance it travelled and its final speed's relative error, against the
  // converged solution of the scenario as written
  double tolerance = 0.01;
  // simulated seconds of the scene the pilot runs at each trial step
  // (capped by the scenario's duration); 0, the default: the whole scene
  // (server/accuracy/pilot.hpp)
  double pilot_duration = 0.0;
  // without a pilot_duration: the share of the run's predicted work the
  // pilot may take (a scout chooses first, and the pilot runs over the
  // longest segment that share affords); 0, the default: the whole scene,
  // up to 60 s (server/accuracy/pilot.hpp, PilotOptions::max_share)
  double pilot_share = 0.0;
  // also pilot RK4 and the adaptive integrator on the ground's friction
  // made regularized, where it is stick-slip or sign (a model the pilot
  // admits only within a third of the tolerance; off by default: it
  // doubles the pilot of a stick-slip scene)
  bool regularized_friction = false;
  // the live estimate (a shadow stepped at half the step over sampled
  // windows) while the run goes
  bool live_estimate = true;
  // refinement at a safe point (server/accuracy/refinement.hpp): when the
  // live estimate of the run's setting passes the tolerance, twice the
  // integrator substeps per step from the next safe point on, at most
  // max_refinements times (needs the live estimate)
  bool refine = true;
  int max_refinements = 3;
};

}  // namespace groundsim::scenario
