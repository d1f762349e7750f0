// The pilot's insides, shared by its source files and by nothing else:
// pilot_trial.cpp (the error law's fit and one fixed-step integrator's
// trial), pilot_adaptive.cpp (the adaptive integrator's trial) and pilot.cpp
// (the models, the pick, the choice).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "accuracy/pilot.hpp"
#include "accuracy/trajectory.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::accuracy::pilot_detail {

inline constexpr double kLadderTop = 0.02;  // s: the coarsest step considered
// differences below this are roundoff: the runs agree
inline constexpr double kRoundoff = 1e-13;

// "%.3g"
std::string fmt(double x);

// The scene of s with these settings, or nullopt with the reason in
// t.refusal when the scenario layer refuses it.
std::optional<scenario::Scene> buildOrRefuse(const scenario::Scenario& s, IntegratorKind kind, double dt,
                                             int contact_substeps, double local_tolerance, IntegratorTrial& t);

// The coarsest ladder step (dt0 / 2^k, k >= 0) whose predicted error, times
// the safety factor, is within the tolerance; 0 when none down to min_dt.
double stepMeeting(const IntegratorTrial& t, double tolerance, const PilotOptions& o);

// Fits t's error law on the last three runs (steps hs: h, h/2, h/4; the
// adaptive integrator's pseudo-steps).
void fit(IntegratorTrial& t, const std::vector<Trajectory>& r, const std::vector<double>& hs, double segment,
         double duration);

// A fit is clean when the differences shrink at close to the integrator's
// order: then extrapolating below the pilot's finest step is trusted.
// stalled: the pair of runs before the fitted three says the differences
// did not shrink (pilot_trial.cpp).
bool stalled(const IntegratorTrial& t);
bool clean(const IntegratorTrial& t);

// One fixed-step integrator's trial: runs at dt0, dt0/2, dt0/4 (dt0 the
// ladder's top within the stability limit, halved after a divergence),
// refined while the fit is not clean. floor: the contact substeps floor, 0
// for the family's (contact's need at dt0); finest_run: the finest healthy
// run, for the caller.
IntegratorTrial trial(const scenario::Scenario& s, IntegratorKind kind, double segment, double top,
                      double tolerance, const PilotOptions& o, int floor, Trajectory& finest_run);

// The adaptive integrator's trial (IntegratorTrial::output_dt), in
// pilot_adaptive.cpp.
IntegratorTrial adaptiveTrial(const scenario::Scenario& s, double segment, double top, double tolerance,
                              const PilotOptions& o, Trajectory& finest_run);

// How long the pilot's runs are, and the top of the ladder
// (pilot_budget.cpp).
struct PilotPlan {
  bool whole = true;           // the whole scene, up to kWholePilotCap
  double duration = 0.0;       // simulated s per trial
  double short_segment = 0.0;  // the fallback of a trial the work budget refuses whole
  double top = 0.0;            // the coarsest ladder step offered
  bool scout = false;          // a first, short pilot whose choice bounds the next one's segment
};
inline constexpr double kWholePilotCap = 60.0;  // s: the longest scene piloted whole

// The first pilot: the segment given, the whole scene when it is short or
// the pilot is not bounded (max_share 0), else the scout.
PilotPlan planPilot(const scenario::Scenario& s, const PilotOptions& o);

// After the scout chose: the longest segment whose pilot, with the
// scout's work, stays within the bound (PilotOptions::max_share of the
// run's predicted work, at least min_pilot_work), when it is at least twice
// the scout's; nullopt: the scout's choice stands. Says how in
// scout.pilot_bound.
std::optional<PilotPlan> extendedPlan(const scenario::Scenario& s, const PilotOptions& o, const PilotPlan& scout,
                                      Choice& scouted);

// What the pilot's runs took, in work units: every trial's evaluations
// times its model's work per evaluation (the models kept out included).
double pilotWork(const Choice& c);

// The coarsest ladder step at or below top inside kStabilityMargin of the
// limit (infinite: no stiff mode), where the stability check starts to warn.
double stableLadderStep(double top, double limit);

// The least work per simulated s integrator k can cost on s: its force
// evaluations of one step (the second: the first may prime a cache) at
// its coarsest stable ladder step, over that step, times the model's work
// per evaluation. Infinite when the scene refuses k. The adaptive
// integrator's steps follow its error, not a limit: 0 (never ruled out).
double leastWork(const scenario::Scenario& s, IntegratorKind k, double top, double work_per_evaluation);

}  // namespace groundsim::accuracy::pilot_detail
