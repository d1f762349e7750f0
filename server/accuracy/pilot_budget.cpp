// The pilot's cost: how long its runs are (the whole scene, or a scout and
// the segment the run's predicted cost affords), what it took, and the
// least an integrator can cost (an integrator that cannot be cheaper than a
// setting already known to meet the tolerance is not piloted).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "accuracy/pilot_detail.hpp"
#include "physics/checks/stability.hpp"
#include "physics/simulator.hpp"

namespace groundsim::accuracy::pilot_detail {

// The measure reads the final speed, at the run's end, and takes the
// largest path error over the whole run: a pilot that stops short of it
// samples the speed error at another moment and leaves whatever happens
// later to the growth law (step 5 of docs/accuracy.md). So a scene is
// piloted whole while that is cheap (a short scene, or a bound the run's
// cost affords), from a scout's choice otherwise.
PilotPlan planPilot(const scenario::Scenario& s, const PilotOptions& o) {
  PilotPlan p;
  p.whole = !(o.pilot_duration > 0.0);
  p.duration = std::min(s.duration, p.whole ? kWholePilotCap : o.pilot_duration);
  // a step longer than the output period would skip frames
  p.top = ladderStepAtMost(std::min(kLadderTop, 1.0 / s.output_rate));
  if (p.whole && o.max_share > 0.0 && p.duration > 2.0 * o.scout_duration) {
    p.whole = false;
    p.scout = true;
    p.duration = o.scout_duration;
  }
  p.short_segment = std::min(p.duration, o.fallback_duration);
  return p;
}

std::optional<PilotPlan> extendedPlan(const scenario::Scenario& s, const PilotOptions& o, const PilotPlan& scout,
                                      Choice& scouted) {
  const double full = std::min(s.duration, kWholePilotCap);
  const double spent = std::max(scouted.pilot_work, 1.0);
  const double bound = std::max(o.max_share * scouted.run_work, o.min_pilot_work);
  // work grows with the segment: what is left of the bound, in scouts
  const double affords = std::floor((bound - spent) / spent * scout.duration / scout.top) * scout.top;
  char buf[320], floor[64] = "";
  if (o.min_pilot_work > 0.0) std::snprintf(floor, sizeof floor, " (at least %.3g)", o.min_pilot_work);
  std::snprintf(buf, sizeof buf,
                "a scout over %.3g s took %.3g work units; the run is predicted %.3g, and the pilot may take %.0f%% "
                "of it%s: %.3g",
                scout.duration, spent, scouted.run_work, 100.0 * o.max_share, floor, bound);
  scouted.pilot_bound = buf;
  if (!(affords >= 2.0 * scout.duration)) {
    scouted.pilot_bound += ", which affords no segment twice the scout's: the scout's choice stands" +
                           std::string(o.other_models ? " (no other model piloted)" : "");
    return std::nullopt;
  }
  PilotPlan p = scout;
  p.scout = false;
  p.whole = affords >= full;
  p.duration = std::min(full, affords);
  p.short_segment = std::min(p.duration, o.fallback_duration);
  std::snprintf(buf, sizeof buf, ", so the pilot ran %s (%.3g s)", p.whole ? "the whole scene" : "a segment",
                p.duration);
  scouted.pilot_bound += buf;
  return p;
}

double pilotWork(const Choice& c) {
  double work = 0.0;
  for (const IntegratorTrial& t : c.trials) work += t.pilot_evaluations * t.work_per_evaluation;
  for (const ModelTrial& m : c.models)
    if (!m.admitted)
      for (const IntegratorTrial& t : m.trials) work += t.pilot_evaluations * t.work_per_evaluation;
  return work;
}

double leastWork(const scenario::Scenario& s, IntegratorKind k, double top, double work_per_evaluation) {
  if (k == IntegratorKind::Adaptive) return 0.0;
  IntegratorTrial refused;
  const std::optional<scenario::Scene> scene = buildOrRefuse(s, k, top, 1, 0.0, refused);
  if (!scene) return std::numeric_limits<double>::infinity();
  double limit = std::numeric_limits<double>::infinity();
  for (const StiffMode& m : stiffestModes(*scene->built.model)) limit = std::min(limit, m.dt_limit);
  const double dt0 = stableLadderStep(top, limit);
  // contact between bodies off: its substeps are extra, and the least is
  // the integrator's own evaluations of a step
  scenario::Scenario apart = s;
  apart.options.collision.enabled = false;
  const std::optional<scenario::Scene> at = buildOrRefuse(apart, k, dt0, 1, 0.0, refused);
  if (!at) return std::numeric_limits<double>::infinity();
  Simulator sim(at->built.model, at->built.initial);
  sim.step();
  const long long first = sim.forceEvaluations();
  sim.step();
  const double per_step = static_cast<double>(std::max(1LL, sim.forceEvaluations() - first));
  return per_step / dt0 * work_per_evaluation;
}

}  // namespace groundsim::accuracy::pilot_detail
