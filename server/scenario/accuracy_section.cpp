#include "scenario/sections.hpp"

namespace groundsim::scenario {

AccuracySpec readAccuracy(ObjectReader r) {
  const AccuracySpec def;
  AccuracySpec a;
  // below 1e-6 the converged reference itself (a step near the floor of
  // the ladder) is not that exact; at 1 the error may be as large as the path
  a.tolerance = r.number("tolerance", def.tolerance, Range::closed(1e-6, 1.0));
  a.pilot_duration = r.number("pilot_duration", def.pilot_duration, Range::closed(0.05, 60.0));
  a.pilot_share = r.number("pilot_share", def.pilot_share, Range::closed(0.0, 100.0));
  a.regularized_friction = r.boolean("regularized_friction", def.regularized_friction);
  a.live_estimate = r.boolean("live_estimate", def.live_estimate);
  a.refine = r.boolean("refine", def.refine);
  // 2^6 = 64 times the chosen step's work at most
  a.max_refinements = r.integer("max_refinements", def.max_refinements, 0, 6);
  r.finish();
  return a;
}

}  // namespace groundsim::scenario
