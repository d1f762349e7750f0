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

}  // namespace groundsim::accuracy::pilot_detail
