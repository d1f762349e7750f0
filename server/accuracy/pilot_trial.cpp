// The pilot's trial of one fixed-step integrator, and the fit of the error
// law both kinds of trial share.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "accuracy/error_measure.hpp"
#include "accuracy/pilot_detail.hpp"
#include "physics/checks/stability.hpp"
#include "physics/forces/body_contact.hpp"
#include "physics/integrators/integrator.hpp"

namespace groundsim::accuracy::pilot_detail {

double stableLadderStep(double top, double limit) {
  return ladderStepAtMost(std::min(top, kStabilityMargin * (1 - 1e-9) * limit));
}

std::string fmt(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

std::optional<scenario::Scene> buildOrRefuse(const scenario::Scenario& s, IntegratorKind kind, double dt,
                                             int contact_substeps, double local_tolerance, IntegratorTrial& t) {
  std::optional<scenario::Scene> scene;
  try {
    scene = scenario::buildScene(withSettings(s, kind, dt, contact_substeps, local_tolerance));
  } catch (const scenario::ScenarioError& e) {
    t.refusal = e.lines("; ");
  }
  return scene;
}

double stepMeeting(const IntegratorTrial& t, double tolerance, const PilotOptions& o) {
  for (double h = t.dt0; h >= o.min_dt * (1 - 1e-9); h /= 2)
    if (t.error(h) * o.safety <= tolerance) return h;
  return 0.0;
}

void fit(IntegratorTrial& t, const std::vector<Trajectory>& r, const std::vector<double>& hs, double segment,
         double duration) {
  const size_t n = r.size();
  const Trajectory &a = r[n - 3], &b = r[n - 2], &c = r[n - 1];
  const RunError fine = compareRuns(b, c);
  t.diff_coarse = compareRuns(a, b).value();
  t.diff_fine = fine.value();
  t.diff_before = n >= 4 ? compareRuns(r[n - 4], a).value() : 0.0;
  const ErrorFit f = fitErrorLaw(t.diff_coarse, t.diff_fine, nominalOrder(t.kind));
  t.order = f.order;
  t.raw_order = t.diff_fine > 0.0 && t.diff_coarse > 0.0 ? std::log2(t.diff_coarse / t.diff_fine) : 0.0;
  // how the error grows over the segment: the fine pair's path error over
  // the first half against the whole, E ~ t^q, carried to the duration
  const size_t half = (c.positions.size() + 1) / 2;
  const double e_half = compareRuns(b, c, half).path, e_all = fine.path;
  t.growth = e_half > kRoundoff && e_all > kRoundoff ? std::clamp(std::log2(e_all / e_half), 0.0, 2.0) : 0.0;
  const double scale = std::pow(std::max(1.0, duration / segment), t.growth);
  const double finest = hs[n - 1];
  t.error_constant = f.e_fine * scale / std::pow(finest, t.order);
  // each pilot step's error as measured: its difference to the finest run
  // plus that run's error (the triangle inequality; a coarse step out of
  // the asymptotic range is not credited with the fitted law's smaller
  // value). Against the finest run directly, not the chain of differences
  // between neighbours: where the runs scatter about the solution (a path
  // that is sensitive to its step, e.g. rims in stick-slip), the chain adds
  // every scatter up and charges a coarse step several times its error.
  t.level_dt.assign(n, 0.0);
  t.level_error.assign(n, 0.0);
  t.level_windows.assign(n, -1.0);
  for (size_t k = 0; k < n; ++k) {
    t.level_windows[k] = r[k].windows;
    const double e = f.e_fine + (k + 1 < n ? compareRuns(r[k], c).value() : 0.0);
    t.level_dt[k] = hs[k];
    t.level_error[k] = e * scale;
  }
  // the cost: force evaluations per step (contact substeps included), a
  // count, not a timing, so the same scene always gets the same choice (a
  // wall-clock cost picked differently under load, and two make_vec calls
  // of one seed ran different settings)
  long long steps = 0, evaluations = 0;
  for (const Trajectory& x : r) {
    steps += x.steps;
    evaluations += x.evaluations;
  }
  t.step_cost = static_cast<double>(evaluations) / static_cast<double>(std::max(1LL, steps));
}

// With a pair of runs before the fitted three, that pair's ratio must not
// say the differences stalled: a law that holds on one ratio after
// differences that did not shrink (the lone wheel's Verlet over the kerb:
// 3.84e-2, 3.76e-2, then 7.78e-3, a clean-looking order 2.3 that read its
// error at 1.25 ms 6x low) is refined once more before it is trusted.
bool stalled(const IntegratorTrial& t) {
  return t.diff_before > 0.0 && !(t.diff_before > 1.05 * t.diff_coarse);
}
bool clean(const IntegratorTrial& t) {
  if (t.diff_coarse < kRoundoff && t.diff_fine < kRoundoff) return true;
  return t.diff_coarse > 1.05 * t.diff_fine && std::abs(t.raw_order - nominalOrder(t.kind)) <= 0.5 && !stalled(t);
}

namespace {

constexpr int kMaxHalvings = 6;  // pilot retries after a divergence

// The stiffest mode of the scene's model under its integrator: the one
// whose step limit is smallest.
const StiffMode* stiffest(const std::vector<StiffMode>& modes) {
  const StiffMode* best = nullptr;
  for (const StiffMode& m : modes)
    if (!best || m.dt_limit < best->dt_limit) best = &m;
  return best;
}

// Each run's step: its duration over its steps.
std::vector<double> stepsOf(const std::vector<Trajectory>& r) {
  std::vector<double> h;
  for (const Trajectory& x : r) h.push_back(x.duration / static_cast<double>(std::max<long long>(1, x.steps)));
  return h;
}

// One trial() call: its state (the trial, what it had to avoid, the work
// spent) and its steps.
class FixedStepTrial {
 public:
  FixedStepTrial(const scenario::Scenario& s, IntegratorKind kind, double segment, double tolerance,
                 const PilotOptions& o, int floor)
      : s_(s), kind_(kind), segment_(segment), tolerance_(tolerance), o_(o), floor_(floor) {
    t_.kind = kind;
  }

  IntegratorTrial run(double top, Trajectory& finest_run) {
    const std::optional<scenario::Scene> scene = buildOrRefuse(s_, kind_, top, 1, 0.0, t_);
    if (!scene) return t_;
    double dt = stableTop(*scene, top);
    // the trial's runs together stay within the work budget (budget.hpp: steps
    // times the model's cost of a step), as one run of the scene must
    step_work_ = std::max(1.0, scenario::estimateModelSize(s_).work_per_step);
    for (int attempt = 0; attempt <= kMaxHalvings; ++attempt, dt /= 2) {
      if (dt / 4 < o_.min_dt * (1 - 1e-9)) break;
      std::vector<Trajectory> r;
      long long steps = 0;
      const Runs runs = runThree(dt, r, steps);
      if (runs == Runs::OverBudget) {
        t_.refusal = avoided_;
        return t_;
      }
      if (runs == Runs::Diverged) continue;
      t_.dt0 = r.front().duration / static_cast<double>(std::max<long long>(1, r.front().steps));
      fit(t_, r, stepsOf(r), segment_, s_.duration);
      const double finest = refine(r, steps, dt / 4);
      accept(r, finest, finest_run);
      return t_;
    }
    t_.refusal = (avoided_.empty() ? "" : avoided_ + "; ") + "no step down to " + fmt(o_.min_dt) + " s stays healthy";
    return t_;
  }

 private:
  enum class Runs { Healthy, Diverged, OverBudget };

  // Stability before accuracy: no step the check of the chosen scene would
  // warn about (physics/checks/stability.cpp warns from kStabilityMargin of
  // a mode's limit on) is run or offered; the pilot's top step is run, so
  // what is offered near the limit is judged by runs, not extrapolated.
  // The first dt0 to try.
  double stableTop(const scenario::Scene& scene, double top) {
    const std::vector<StiffMode> modes = stiffestModes(*scene.built.model);
    const StiffMode* worst = stiffest(modes);
    t_.stability_dt = worst ? worst->dt_limit : std::numeric_limits<double>::infinity();
    const double dt = stableLadderStep(top, t_.stability_dt);
    if (worst && dt < top)
      avoided_ = "steps above " + fmt(dt) + " s pass " + fmt(100 * kStabilityMargin) +
                 "% of the limit of the stiffest mode (" + worst->what + ", stable below " + fmt(worst->dt_limit) +
                 " s)";
    return dt;
  }

  void note(const std::string& why) { avoided_ += (avoided_.empty() ? "" : "; ") + why; }

  bool afford(double h, int substeps) {
    const double work = std::ceil(segment_ / h) * std::max(1, substeps) * step_work_;
    if (spent_ + work > o_.max_work) return false;
    spent_ += work;
    return true;
  }

  Trajectory runAt(double h) {
    Trajectory r = runTrajectory(withSettings(s_, kind_, h, t_.contact_substeps), segment_, nominalOrder(kind_));
    t_.pilot_evaluations += static_cast<double>(r.evaluations);
    return r;
  }

  // The runs at dt, dt/2, dt/4 into r (their steps added to steps); contact's
  // substeps at dt become the family's floor.
  Runs runThree(double dt, std::vector<Trajectory>& r, long long& steps) {
    t_.contact_substeps =
        floor_ > 0 ? floor_ : contactSubstepsBound(*scenario::buildScene(withSettings(s_, kind_, dt)).built.model, dt);
    for (int k = 0; k < 3; ++k) {
      if (!afford(dt / (1 << k), t_.contact_substeps)) {
        note("the pilot's run at dt " + fmt(dt / (1 << k)) + " s would pass the work budget (" + fmt(o_.max_work) +
             " units, --max-work)");
        return Runs::OverBudget;
      }
      r.push_back(runAt(dt / (1 << k)));
      steps += r.back().steps;
      if (!r.back().healthy) {
        note("dt " + fmt(dt / (1 << k)) + " s diverged in the pilot (" + r.back().failure + ")");
        return Runs::Diverged;
      }
    }
    return Runs::Healthy;
  }

  // A fit that is not clean is not extrapolated far: while the step it asks
  // for lies below the finest run, run finer and fit again. A stalled one is
  // not trusted at its finest run either (that run's error is the fit's word
  // alone): while it asks for that run, refine too. A clean one asking for a
  // step below its finest run is judged by one run more, a step finer, before
  // it is extrapolated: three runs that shrink at the order by chance (a
  // chaotic scene: the washboard's Verlet, 0.27, 0.053, 0.0096, then 0.039
  // at the next step) are not a law: where that run breaks it, the trial
  // ends there, its finest error that run's (one run more, not a descent).
  // The finest step run.
  double refine(std::vector<Trajectory>& r, long long steps, double finest) {
    for (bool confirmed = false;;) {
      const double want = stepMeeting(t_, tolerance_, o_);
      const bool law = clean(t_);
      if (law) {
        if (confirmed || !(want < finest * (1 - 1e-9))) break;
        confirmed = true;
      } else if (confirmed || want > (stalled(t_) ? finest * (1 + 1e-9) : finest * (1 - 1e-9))) {
        break;  // (a law the confirming run broke: nothing is credited below that run, no more is spent)
      }
      if (finest / 2 < o_.min_dt * (1 - 1e-9)) break;
      const long long more = std::llround(segment_ / (finest / 2));
      if (steps + more > o_.max_pilot_steps || !afford(finest / 2, t_.contact_substeps)) {
        note(law ? "its law (order " + fmt(t_.order) + ") is extrapolated below dt " + fmt(finest) +
                       " s unconfirmed: a run finer would pass the pilot's step or work budget"
                 : "the fit is not clean (order " + fmt(t_.order) + ") and refining it below dt " + fmt(finest) +
                       " s would pass the pilot's step or work budget");
        break;
      }
      r.push_back(runAt(finest / 2));
      steps += more;
      if (!r.back().healthy) {
        r.pop_back();
        break;
      }
      finest /= 2;
      fit(t_, r, stepsOf(r), segment_, s_.duration);
    }
    return finest;
  }

  // The trial usable, its law said clean or not, its finest run handed out.
  void accept(std::vector<Trajectory>& r, double finest, Trajectory& finest_run) {
    t_.clean_fit = clean(t_);
    if (!t_.clean_fit)
      note("its error law is not clean (observed order " + fmt(t_.raw_order) + ", nominal " +
           std::to_string(nominalOrder(kind_)) + "): below dt " + fmt(finest) +
           " s no error is credited beyond that run's");
    finest_run = std::move(r.back());
    t_.usable = true;
    t_.refusal = avoided_;
  }

  const scenario::Scenario& s_;
  const IntegratorKind kind_;
  const double segment_, tolerance_;
  const PilotOptions& o_;
  const int floor_;
  IntegratorTrial t_;
  std::string avoided_;  // what the trial had to avoid, or why it failed
  double step_work_ = 1.0, spent_ = 0.0;
};

}  // namespace

IntegratorTrial trial(const scenario::Scenario& s, IntegratorKind kind, double segment, double top,
                      double tolerance, const PilotOptions& o, int floor, Trajectory& finest_run) {
  return FixedStepTrial(s, kind, segment, tolerance, o, floor).run(top, finest_run);
}

}  // namespace groundsim::accuracy::pilot_detail
