// Refinement at a safe point: a run with a tolerance whose live estimate
// says its setting errs by more than the tolerance takes twice the
// integrator substeps per step from the next safe point on, up to
// max_refinements times; when it cannot (refinement off, or none left)
// it warns once. The same policy serves `groundsim run` and the sessions
// (a session also logs the refinement as an applied entry, so that a
// re-simulation refines at the same tick). docs/accuracy.md, "Refinement".
#pragma once

#include <string>
#include <vector>

#include "accuracy/live_estimate.hpp"
#include "accuracy/trajectory.hpp"
#include "physics/simulator.hpp"
#include "scenario/accuracy_spec.hpp"

namespace groundsim::accuracy {

struct RefinementPolicy {
  double tolerance = 0.0;   // 0: none (no refinement, no warning)
  bool refine = true;       // accuracy.refine
  int max_refinements = 3;  // accuracy.max_refinements: at most 2^this substeps per step
};
RefinementPolicy refinementPolicy(const scenario::AccuracySpec& a);

// A step where the main run may change its step: the end of a step with no
// contact between bodies under way (a hit is resolved in substeps of its
// own and its log reads the step it began in) and the run healthy. The
// caller adds its own condition (a frame boundary: a session's published
// states then come from one setting each, and a window of a frame).
bool safeToRefine(const Simulator& sim);

class Refiner {
 public:
  explicit Refiner(RefinementPolicy p) : p_(p) {}

  struct Decision {
    int substeps = 0;     // > 0: refine to this many substeps now
    std::string message;  // the event's or the warning's text ("" : nothing to say)
    bool warning = false; // the tolerance is passed and no refinement follows
  };
  // After a step of `sim` watched by `live`, at a point where the caller
  // could refine (safe: safeToRefine and its own condition): decides, and
  // when it refines applies it to both (Simulator::refine,
  // LiveEstimate::refine); the caller says it (and a session logs it).
  Decision watch(Simulator& sim, LiveEstimate& live, bool safe);
  // a session's reset: the warning may be given again
  void reset() { warned_ = pending_ = false; }

 private:
  Decision check(const Simulator& sim, const LiveEstimate& live, bool safe);
  RefinementPolicy p_;
  bool warned_ = false;
  bool pending_ = false;  // the estimate asks for one: at the next safe point
  double asked_at_ = 0.0, asked_level_ = 0.0;
};

// A run of s watched by the live estimate (Richardson at `order`, the
// pilot's prediction when given) with this refinement policy, sampled as
// runTrajectory samples (error_measure.hpp compares it), a refinement
// decided at each sample's end: `groundsim run`'s loop, for the tests and
// the benchmark (bench/accuracy/refine_sweep.cpp).
struct RefinedRun {
  Trajectory run;
  double estimate = 0.0;
  struct Refinement {
    long long tick = 0;
    int substeps = 0;
  };
  std::vector<Refinement> refinements;
  std::vector<std::string> messages;  // the decisions' texts, in order
};
RefinedRun runRefined(const scenario::Scenario& s, int order, RefinementPolicy p, const Prediction& prediction = {});

}  // namespace groundsim::accuracy
