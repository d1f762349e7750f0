#include "accuracy/refinement.hpp"

#include <cstdio>

namespace groundsim::accuracy {

bool safeToRefine(const Simulator& sim) { return sim.healthy() && sim.hits().empty(); }

RefinementPolicy refinementPolicy(const scenario::AccuracySpec& a) {
  return {a.tolerance, a.refine, a.max_refinements};
}

Refiner::Decision Refiner::watch(Simulator& sim, LiveEstimate& live, bool safe) {
  Decision d = check(sim, live, safe);
  if (d.substeps > 0) {
    sim.refine(d.substeps);
    live.refine(d.substeps, sim.state().t);
    pending_ = false;
  }
  return d;
}

Refiner::Decision Refiner::check(const Simulator& sim, const LiveEstimate& live, bool safe) {
  Decision d;
  if (!(p_.tolerance > 0.0)) return d;
  const double t = sim.state().t;
  const int substeps = sim.model().opt.substeps;
  const bool can = p_.refine && live.refinements() < p_.max_refinements &&
                   2 * substeps <= Simulator::kMaxSubsteps && !live.shadowFailed();
  // the setting's own error above the tolerance: a finer one is due
  if (can && !pending_ && live.level() > p_.tolerance) {
    pending_ = true;
    asked_at_ = t;
    asked_level_ = live.level();
  }
  if (pending_ && safe) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "accuracy: the live error estimate of the current setting, %.3g at t = %.4g s, passed the "
                  "tolerance %.3g: refined to %d integrator substeps per step (from %d) at t = %.4g s",
                  asked_level_, asked_at_, p_.tolerance, 2 * substeps, substeps, t);
    d.substeps = 2 * substeps;
    d.message = buf;
    return d;
  }
  // a refinement waiting a whole second for a safe point (bodies kept in
  // contact): said once, and the refinement still comes when it can
  if (!warned_ && pending_ && t - asked_at_ > 1.0) {
    warned_ = true;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "accuracy: the live error estimate of the current setting, %.3g at t = %.4g s, passed the "
                  "tolerance %.3g; no safe point to refine at since (contact between bodies under way)",
                  asked_level_, asked_at_, p_.tolerance);
    d.message = buf;
    d.warning = true;
    return d;
  }
  // past the tolerance with no refinement to come: said once. Either none
  // can come, or the setting reads within the tolerance on two windows of
  // its own after a refinement, and what was made before keeps the run's
  // estimate above it. (Before any refinement, an estimate above the
  // tolerance with the setting's level below it is the windows' first
  // reading, which waits for a second: then both agree.)
  const bool settled_within = live.refinements() > 0 && live.settingWindows() >= 2 && live.level() <= p_.tolerance;
  if (!warned_ && !pending_ && live.level() >= 0.0 && live.estimate() > p_.tolerance && (!can || settled_within)) {
    warned_ = true;
    char buf[400];
    std::string why;
    if (settled_within)
      why = " (refined " + std::to_string(live.refinements()) + " times, to " + std::to_string(substeps) +
            " substeps per step: the error made before the last refinement stays)";
    else if (!p_.refine)
      why = " (refinement off: accuracy.refine)";
    else if (live.shadowFailed())
      why = " (the estimate's shadow diverged)";
    else
      why = " (" + std::to_string(substeps) + " substeps per step after " + std::to_string(live.refinements()) +
            " refinements, the most: accuracy.max_refinements)";
    std::snprintf(buf, sizeof buf, "accuracy: the live error estimate %.3g passed the tolerance %.3g at t = %.4g s%s",
                  live.estimate(), p_.tolerance, t, why.c_str());
    d.message = buf;
    d.warning = true;
  }
  return d;
}

RefinedRun runRefined(const scenario::Scenario& s, int order, RefinementPolicy p, const Prediction& prediction) {
  RefinedRun out;
  const scenario::Scene scene = scenario::buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  LiveEstimateOptions o;
  o.duration = s.duration;
  LiveEstimate live(s, order, o);
  live.expect(prediction, s.duration);
  Refiner refiner(p);
  out.run = sampleRun(scene, sim, s.duration, [&](long long n) {
    if (!stepWatched(scene, sim, n, &live)) return false;
    const Refiner::Decision d = refiner.watch(sim, live, safeToRefine(sim));
    if (d.substeps > 0) out.refinements.push_back({sim.state().tick, d.substeps});
    if (!d.message.empty()) out.messages.push_back(d.message);
    return true;
  });
  live.beforeStep(sim);  // a last update at the end
  out.estimate = live.estimate();
  return out;
}

}  // namespace groundsim::accuracy
