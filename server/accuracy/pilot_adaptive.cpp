// The pilot's trial of the adaptive integrator (IntegratorTrial::output_dt):
// runs at local tolerances tau0, tau0/8, tau0/64 (pseudo-steps h, h/2, h/4;
// tau0 the user's tolerance), each covering the output step in internal
// steps, fitted as a fixed step's three runs are, and refined by 8 while the
// fit is not clean and the tolerance asks for less than the finest run. Its
// runs stay within the work budget like a trial's (an evaluation counted as
// a third of a step: the method's three new stages a step).
#include <algorithm>
#include <cmath>
#include <limits>

#include "accuracy/error_measure.hpp"
#include "accuracy/pilot_detail.hpp"
#include "physics/forces/body_contact.hpp"
#include "physics/integrators/integrator.hpp"

namespace groundsim::accuracy::pilot_detail {
namespace {

// One adaptiveTrial() call: its state (the trial, its runs and their
// pseudo-steps, the work and evaluations spent) and its steps.
class AdaptiveTrial {
 public:
  AdaptiveTrial(const scenario::Scenario& s, double segment, double tolerance, const PilotOptions& o)
      : s_(s), segment_(segment), tolerance_(tolerance), o_(o) {}

  IntegratorTrial run(double top, Trajectory& finest_run) {
    t_.kind = IntegratorKind::Adaptive;
    t_.output_dt = top;
    t_.stability_dt = std::numeric_limits<double>::infinity();  // its internal steps follow the error, not a limit
    const double tau0 = std::clamp(tolerance_, o_.min_local_tolerance, 1.0);
    const std::optional<scenario::Scene> scene = buildOrRefuse(s_, IntegratorKind::Adaptive, top, 1, tau0, t_);
    if (!scene) return t_;
    t_.contact_substeps = contactSubstepsBound(*scene->built.model, top);
    step_work_ = std::max(1.0, scenario::estimateModelSize(s_).work_per_step);
    if (!chooseOutputStep(top, tau0)) return t_;
    if (!runLadder(tau0)) return t_;
    refine();
    accept(finest_run);
    return t_;
  }

 private:
  // The next run's force evaluations, guessed: the last ones' growth again
  // (at least 2x), 4 a step for the first.
  double nextEvaluations() const {
    const size_t n = r_.size();
    const double last = n ? static_cast<double>(r_[n - 1].evaluations) : 0.0;
    const double growth =
        n >= 2 ? std::max(2.0, last / std::max(1.0, static_cast<double>(r_[n - 2].evaluations))) : 4.0;
    return n ? last * growth : 4.0 * segment_ / t_.output_dt;
  }

  // False, with the refusal said, when the run at tau would pass the work
  // budget or the bound on the adaptive pilot's evaluations.
  bool afford(double tau, double next) {
    const double guess = next / 3.0 * std::max(1, t_.contact_substeps) * step_work_;
    if (spent_ + guess > o_.max_work) {
      t_.refusal = "the pilot's run at local tolerance " + fmt(tau) + " would pass the work budget (" +
                   fmt(o_.max_work) + " units, --max-work)";
      return false;
    }
    if (o_.max_adaptive_evaluations > 0.0 && evaluations_ + next > o_.max_adaptive_evaluations) {
      t_.refusal = "the pilot's run at local tolerance " + fmt(tau) + " and output step " + fmt(t_.output_dt) +
                   " s would take more force evaluations than twice the scene's own integrators' pilot (" +
                   fmt(o_.max_adaptive_evaluations) + ")";
      return false;
    }
    return true;
  }

  // A run at local tolerance tau and the current output step, appended to
  // the runs. False: not affordable, or it diverged (the refusal says).
  bool runAt(double tau) {
    if (!afford(tau, nextEvaluations())) return false;
    r_.push_back(runTrajectory(withSettings(s_, IntegratorKind::Adaptive, t_.output_dt, t_.contact_substeps, tau),
                               segment_, nominalOrder(IntegratorKind::Adaptive)));
    spent_ += static_cast<double>(r_.back().evaluations) / 3.0 * std::max(1, t_.contact_substeps) * step_work_;
    evaluations_ += static_cast<double>(r_.back().evaluations);
    t_.pilot_evaluations = evaluations_;
    hs_.push_back(std::cbrt(tau));
    if (!r_.back().healthy) {
      t_.refusal = "local tolerance " + fmt(tau) + " diverged in the pilot (" + r_.back().failure + ")";
      return false;
    }
    return true;
  }

  // The output step: what it costs at the top, from two accurate runs (the
  // finest tolerance of the ladder) at the top and half of it, then halved
  // until that is within a fourth of the tolerance (first order).
  bool chooseOutputStep(double top, double tau0) {
    const double probe = tau0 / 64.0;
    double out = top;
    if (!runAt(probe)) return false;
    t_.output_dt = top / 2;
    if (!runAt(probe)) return false;
    const double at_top = 2.0 * compareRuns(r_[0], r_[1]).value();
    r_.clear(), hs_.clear();
    int halvings = 0;
    while (at_top * (out / top) * o_.safety > 0.25 * tolerance_ && out / 2 >= o_.min_dt * (1 - 1e-9) &&
           halvings < o_.max_output_halvings)
      out /= 2, ++halvings;
    t_.output_dt = out;
    t_.tick_offset = at_top * (out / top);
    return true;
  }

  // The runs at tau0, tau0/8, tau0/64, fitted.
  bool runLadder(double tau0) {
    for (int k = 0; k < 3; ++k)
      if (!runAt(tau0 / std::pow(8.0, k))) return false;
    refit();
    t_.dt0 = hs_.front();
    return true;
  }

  // The fit, each level's error with the output step's part.
  void refit() {
    fit(t_, r_, hs_, segment_, s_.duration);
    for (double& e : t_.level_error) e += t_.tick_offset;
  }

  // Refined by 8 while the fit is not clean and the tolerance asks for less
  // than the finest run (a stalled fit: for that run too).
  void refine() {
    PilotOptions oa = o_;
    oa.min_dt = std::cbrt(o_.min_local_tolerance);
    while (!clean(t_)) {
      const double finest = hs_.back();
      const bool asks_finer = stalled(t_) ? stepMeeting(t_, tolerance_, oa) <= finest * (1 + 1e-9)
                                          : stepMeeting(t_, tolerance_, oa) < finest * (1 - 1e-9);
      const double tau = IntegratorTrial::localTolerance(finest) / 8.0;
      if (!asks_finer || tau < o_.min_local_tolerance * (1 - 1e-9)) break;
      if (!runAt(tau)) {
        if (!r_.back().healthy) r_.pop_back(), hs_.pop_back();
        t_.refusal.clear();
        break;
      }
      refit();
    }
  }

  // The trial usable, its law said clean or not, its cost per level, its
  // finest run handed out.
  void accept(Trajectory& finest_run) {
    t_.clean_fit = clean(t_);
    if (!t_.clean_fit)
      t_.refusal = "its error law is not clean (observed order " + fmt(t_.raw_order) +
                   " in tau^(1/3), nominal 3): below local tolerance " +
                   fmt(IntegratorTrial::localTolerance(hs_.back())) + " no error is credited beyond that run's";
    t_.level_cost.clear();
    for (const Trajectory& x : r_)
      t_.level_cost.push_back(static_cast<double>(x.evaluations) / std::max(x.duration, 1e-12));
    t_.step_cost = t_.level_cost.back() * hs_.back();  // evaluations per simulated s times h: cost(h) = this / h below
    finest_run = std::move(r_.back());
    t_.usable = true;
  }

  const scenario::Scenario& s_;
  const double segment_, tolerance_;
  const PilotOptions& o_;
  IntegratorTrial t_;
  std::vector<Trajectory> r_;
  std::vector<double> hs_;   // the runs' pseudo-steps, tau^(1/3)
  double step_work_ = 1.0, spent_ = 0.0;
  double evaluations_ = 0.0;  // so far, in all
};

}  // namespace

IntegratorTrial adaptiveTrial(const scenario::Scenario& s, double segment, double top, double tolerance,
                              const PilotOptions& o, Trajectory& finest_run) {
  return AdaptiveTrial(s, segment, tolerance, o).run(top, finest_run);
}

}  // namespace groundsim::accuracy::pilot_detail
