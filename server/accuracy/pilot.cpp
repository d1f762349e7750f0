// The pilot: the error law's fit, the models, the pick, the choice. One
// fixed-step integrator's trial is in pilot_trial.cpp, the adaptive
// integrator's in pilot_adaptive.cpp.
#include "accuracy/pilot.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "accuracy/error_measure.hpp"
#include "accuracy/model_options.hpp"
#include "accuracy/pilot_detail.hpp"
#include "physics/integrators/integrator.hpp"

namespace groundsim::accuracy {
using pilot_detail::adaptiveTrial;
using pilot_detail::fmt;
using pilot_detail::kLadderTop;
using pilot_detail::kRoundoff;
using pilot_detail::leastWork;
using pilot_detail::PilotPlan;
using pilot_detail::trial;

// Richardson on three runs at h, h/2, h/4: d_coarse = |E(h) - E(h/2)|,
// d_fine = |E(h/2) - E(h/4)|, so p = log2(d_coarse / d_fine) and the error
// of the finest run is d_fine / (2^p - 1). Where the differences do not
// shrink (not yet in the asymptotic range, or a non-smooth event), the
// order is taken as 0.5 and the finest error as the larger difference:
// pessimistic, so a finer step is chosen rather than a wrong one.
ErrorFit fitErrorLaw(double d_coarse, double d_fine, int nominal) {
  if (d_coarse < kRoundoff && d_fine < kRoundoff) return {static_cast<double>(nominal), std::max(d_fine, 1e-16)};
  if (!(d_coarse > 1.05 * d_fine)) return {0.5, std::max(d_coarse, d_fine)};
  // Differences that shrink faster than the integrator's order allows (by
  // more than half an order) say the coarse run is outside the asymptotic
  // range, not that the fine pair converges that fast: one difference is
  // left, which says nothing of the order, so the lowest, 1, is taken (what
  // a non-smooth event, a stick-slip solve or an impact, leaves of any
  // integrator's), and the fit, not clean, is refined when the step the
  // tolerance asks for lies below the finest run. At the clamp (nominal +
  // 0.5) the finest run's error was read 1.8x (semi-implicit Euler) to 4.7x
  // (Verlet) below the fine difference: eight cars at 0.1% realised 3x it.
  const double raw = std::log2(d_coarse / std::max(d_fine, 1e-16));
  const double p = raw > nominal + 0.5 ? 1.0 : std::clamp(raw, 0.5, nominal + 0.5);
  return {p, std::max(d_fine, 1e-16) / (std::pow(2.0, p) - 1.0)};
}

PilotOptions pilotOptions(const scenario::AccuracySpec& a, const scenario::Budget& budget) {
  PilotOptions o;
  o.pilot_duration = a.pilot_duration;
  o.max_share = a.pilot_share;
  o.regularized_friction = a.regularized_friction;
  o.max_work = budget.max_work;
  return o;
}

double ladderStepAtMost(double h) {
  double d = kLadderTop;
  while (d > h * (1.0 + 1e-12) && d > 1e-12) d /= 2;
  return d;
}

int nominalOrder(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::VelocityVerlet: return 2;
    case IntegratorKind::Rk4: return 4;
    case IntegratorKind::Adaptive: return 3;
    case IntegratorKind::SemiImplicitEuler:
    case IntegratorKind::ImplicitEuler: break;
  }
  return 1;
}

double IntegratorTrial::error(double h) const {
  if (level_dt.empty() || h > level_dt.front() * (1 + 1e-9)) return std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < level_dt.size(); ++k)
    if (std::abs(h / level_dt[k] - 1.0) < 1e-9) return model_gap + level_error[k];
  // a law that is not clean is not extrapolated: finer steps keep the finest run's error
  if (!clean_fit) return model_gap + level_error.back();
  return model_gap + contact_offset + tick_offset + error_constant * std::pow(h, order);
}

double IntegratorTrial::cost(double h) const {
  if (level_cost.empty()) return step_cost / h;
  if (level_dt.empty() || h > level_dt.front() * (1 + 1e-9)) return std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < level_dt.size(); ++k)
    if (std::abs(h / level_dt[k] - 1.0) < 1e-9) return level_cost[k];
  return level_cost.back() * level_dt.back() / h;  // finer: steps grow as tau^(-1/3) = 1 / h
}

namespace {

// The trials of one model of the scene, and each one's finest healthy run
// (for the comparison of models).
struct ModelPilot {
  std::vector<IntegratorTrial> trials;
  std::vector<Trajectory> finest;  // per trial (empty when not usable)
};

// One integrator on one model: its trial at the refined contact substeps
// and, with contact between bodies, at the automatic ones.
void pilotIntegrator(const scenario::Scenario& s, IntegratorKind k, double tolerance, const PilotOptions& o,
                     double pilot_duration, double short_segment, bool whole, double top, ModelPilot& out) {
  Trajectory refined, automatic;
  double segment = pilot_duration;
  if (k == IntegratorKind::Adaptive) {  // its own tolerance ladder, its contact substeps what contact needs at top
    IntegratorTrial a = adaptiveTrial(s, segment, top, tolerance, o, refined);
    if (!a.usable && whole && segment > short_segment && a.refusal.find("--max-work") != std::string::npos) {
      segment = short_segment;
      a = adaptiveTrial(s, segment, top, tolerance, o, refined);
    }
    a.segment = segment;
    out.trials.push_back(a);
    out.finest.push_back(a.usable ? refined : Trajectory{});
    return;
  }
  IntegratorTrial first = trial(s, k, segment, top, tolerance, o, 0, refined);
  if (!first.usable && whole && segment > short_segment && first.refusal.find("--max-work") != std::string::npos) {
    segment = short_segment;
    first = trial(s, k, segment, top, tolerance, o, 0, refined);
  }
  first.segment = segment;
  out.trials.push_back(first);
  out.finest.push_back(first.usable ? refined : Trajectory{});
  const IntegratorTrial& tf = out.trials.back();
  if (!tf.usable || tf.contact_substeps <= 1) return;
  // With contact between bodies, also the automatic substeps (cheaper:
  // contact only as finely as stability asks). Its own differences cannot
  // see contact's error, since contact's substep does not shrink with its
  // step: its finest run's error is bounded instead through the refined
  // family (the triangle inequality): the gap between the two finest runs
  // plus the refined one's error. That replaces its own Richardson error
  // in each of its steps' errors (adding both charged the integration
  // error twice: eight cars at 0.1%, the automatic substeps at 1.25 ms
  // charged 1.6e-3, realised 7e-4, and 5x the oracle's cost taken).
  IntegratorTrial ta = trial(s, k, segment, top, tolerance, o, 1, automatic);
  ta.segment = segment;
  if (ta.usable) {
    const double scale = std::pow(std::max(1.0, s.duration / segment), tf.growth);
    ta.contact_offset = compareRuns(automatic, refined).value() * scale + tf.level_error.back();
    const double own = ta.level_error.back();  // its finest run's Richardson error
    for (double& e : ta.level_error) e += ta.contact_offset - own;
  }
  out.trials.push_back(ta);
  out.finest.push_back(ta.usable ? automatic : Trajectory{});
}

// The most accurate run a model's pilot has: the finest run of the trial
// whose error there is smallest; -1 when no trial is usable.
int mostAccurate(const ModelPilot& m) {
  int best = -1;
  for (size_t i = 0; i < m.trials.size(); ++i)
    if (m.trials[i].usable &&
        (best < 0 || m.trials[i].level_error.back() < m.trials[static_cast<size_t>(best)].level_error.back()))
      best = static_cast<int>(i);
  return best;
}

// The distance between two models' converged solutions, bounded by their
// most accurate runs (the triangle inequality): the runs' difference, grown
// to the whole duration as the user's errors grow, plus each run's error.
void boundModelGap(const ModelPilot& user, const ModelPilot& other, double duration, ModelTrial& m) {
  const int u = mostAccurate(user), a = mostAccurate(other);
  m.gap = std::numeric_limits<double>::infinity();
  if (u < 0 || a < 0) return;
  const IntegratorTrial &tu = user.trials[static_cast<size_t>(u)], &ta = other.trials[static_cast<size_t>(a)];
  const Trajectory &ru = user.finest[static_cast<size_t>(u)], &ra = other.finest[static_cast<size_t>(a)];
  // runs of different lengths (one model's trials fell back to a shorter
  // segment) compare over their common samples, the path alone
  const bool same = std::abs(ru.duration - ra.duration) < 1e-9;
  const size_t common = std::min(ru.positions.size(), ra.positions.size());
  const RunError d = compareRuns(ra, ru, same ? static_cast<size_t>(-1) : common - 1);
  const double segment = std::min(ru.duration, ra.duration);
  m.difference = d.value() * std::pow(std::max(1.0, duration / std::max(segment, 1e-9)), tu.growth);
  m.user_error = tu.level_error.back();
  m.own_error = ta.level_error.back();
  m.gap = m.difference + m.user_error + m.own_error;
  // the same integrator at the same step giving the same bits under both
  // models: the law that differs never acted on that run (a road car's
  // tyres do not use the ground's friction), so the models are one there
  if (same && tu.kind == ta.kind && std::abs(tu.level_dt.back() / ta.level_dt.back() - 1.0) < 1e-9 &&
      d.value() == 0.0 && ru.final_velocity == ra.final_velocity)
    m.gap = 0.0;
}

// The steps of the user's model's pilot with integrator k (the larger of
// its families'): another model's pilot of k refines no further than that,
// so screening a model costs at most what piloting the user's did (the
// crash's stick-slip tyres, kept out at 1%, had refined their automatic
// substeps down to 2e-5 s: 4x the user's pilot).
long long pilotSteps(const ModelPilot& m, IntegratorKind k) {
  long long most = 0;
  for (const IntegratorTrial& t : m.trials) {
    if (t.kind != k || !t.usable) continue;
    long long n = 0;
    for (double h : t.level_dt) n += std::llround(t.segment / h);
    most = std::max(most, n);
  }
  return most;
}

// The force evaluations of the most costly usable fixed-step trial (its
// runs together); 0 when none ran (then nothing bounds the adaptive trial
// but the work budget).
double mostEvaluations(const ModelPilot& m) {
  double most = 0.0;
  for (const IntegratorTrial& t : m.trials) {
    if (!t.usable || t.adaptive()) continue;
    double n = 0.0;
    for (double h : t.level_dt) n += t.segment / h * t.step_cost;
    most = std::max(most, n);
  }
  return most;
}

}  // namespace

namespace {

// The trial and step taken: the cheapest (in work, which compares models)
// whose predicted error times the safety factor is within the tolerance,
// or, when none is, the closest (meets false; no trial: none usable).
struct Pick {
  const IntegratorTrial* trial = nullptr;
  double dt = 0.0;
  bool meets = false;
  double work = std::numeric_limits<double>::infinity();  // per simulated s, when it meets
};

Pick cheapest(const std::vector<IntegratorTrial>& trials, double tolerance, const PilotOptions& o) {
  Pick best, closest;
  double closest_err = std::numeric_limits<double>::infinity();
  for (const IntegratorTrial& t : trials) {
    if (!t.usable) continue;
    const double finest_h = t.adaptive() ? std::cbrt(o.min_local_tolerance) : o.min_dt;
    for (double h = t.dt0; h >= finest_h * (1 - 1e-9); h /= 2) {
      const double err = t.error(h), cost = t.cost(h) * t.work_per_evaluation;
      if (err < closest_err) {
        closest_err = err;
        closest = {&t, h, false};
      }
      if (err * o.safety <= tolerance) {
        if (cost < best.work) best = {&t, h, true, cost};
        break;  // finer steps of this integrator only cost more
      }
    }
  }
  return best.trial ? best : closest;
}

// cheapest(), throwing naming every refusal when no trial ran at all.
Pick pickCheapest(const std::vector<IntegratorTrial>& trials, double tolerance, const PilotOptions& o) {
  const Pick p = cheapest(trials, tolerance, o);
  if (p.trial) return p;
  std::vector<scenario::Issue> issues;
  for (const IntegratorTrial& t : trials)
    issues.push_back({"/physics/integrator", std::string(integratorName(t.kind)) + ": " + t.refusal});
  throw scenario::ScenarioError(std::move(issues));
}

// Branch and bound: an integrator whose least work per simulated s (at its
// coarsest stable step, pilot_budget.cpp) is no less than that of a setting
// already known to meet the tolerance cannot be chosen, so it is not
// piloted; it stays in the trials, not usable, saying why. The same choice
// as piloting it, for less.
bool ruledOut(const scenario::Scenario& s, IntegratorKind k, double top, double work_per_evaluation,
              const std::vector<IntegratorTrial>& known, double tolerance, const PilotOptions& o, ModelPilot& out) {
  const Pick best = cheapest(known, tolerance, o);
  if (!best.meets) return false;
  const double least = leastWork(s, k, top, work_per_evaluation);
  if (!(least >= best.work) || std::isinf(least)) return false;  // inf: refused, and its trial says why
  IntegratorTrial t;
  t.kind = k;
  t.work_per_evaluation = work_per_evaluation;
  t.refusal = "not piloted: at its coarsest stable step it costs at least " + fmt(least) +
              " work units per sim-s, no less than " + integratorName(best.trial->kind) + " at dt " + fmt(best.dt) +
              " s (" + fmt(best.work) + "), which meets the tolerance";
  out.trials.push_back(t);
  out.finest.emplace_back();
  return true;
}

// Model fidelity: a cheaper model the core offers for these vehicles is
// piloted like the user's, first with the integrator whose run of the
// user's model is the most accurate (u; that pair bounds the two converged
// solutions' distance); only where that bound is within kModelShare of the
// tolerance are its other integrators piloted and its trials, their errors
// raised by the bound, offered to the choice (c.trials).
void pilotModel(const ModelOption& option, const ModelPilot& user, int u, double tolerance, const PilotOptions& o,
                const PilotPlan& plan, double duration, Choice& c) {
  ModelTrial m;
  m.name = option.name;
  m.what = option.what;
  if (u < 0) {
    m.gap = std::numeric_limits<double>::infinity();
    m.verdict = "not piloted: no integrator runs the scene as written, so nothing to compare it with";
    c.models.push_back(m);
    return;
  }
  const double own = user.trials[static_cast<size_t>(u)].level_error.back();
  if (!(own <= kModelShare * tolerance)) {
    // the user's own model is not known to the share a model may take: a
    // difference from it cannot be bounded there (the report's 20-point
    // rims in stick-slip: their runs scatter with the step by percent)
    m.gap = std::numeric_limits<double>::infinity();
    m.user_error = own;
    m.verdict = "not piloted: the scene as written is known only to " + fmt(own) +
                " (its most accurate pilot run), more than " + fmt(kModelShare) +
                " of the tolerance, so no other model can be shown within it";
    c.models.push_back(m);
    return;
  }
  const double work = workPerEvaluation(option.scenario);
  auto offered = [&](IntegratorKind k) {
    return option.only.empty() || std::find(option.only.begin(), option.only.end(), k) != option.only.end();
  };
  // a model none of whose integrators can be cheaper than the choice the
  // scene as written already has is not piloted
  const Pick best = cheapest(c.trials, tolerance, o);
  double least = std::numeric_limits<double>::infinity();
  for (IntegratorKind k : o.integrators)
    if (best.meets && offered(k)) least = std::min(least, leastWork(option.scenario, k, plan.top, work));
  if (best.meets && least >= best.work) {
    m.gap = std::numeric_limits<double>::infinity();
    m.verdict = "not piloted: at its coarsest stable steps it costs at least " + fmt(least) +
                " work units per sim-s, no less than the " + fmt(best.work) +
                " of a setting of the scene as written that meets the tolerance";
    c.models.push_back(m);
    return;
  }
  ModelPilot other;
  const IntegratorKind first = user.trials[static_cast<size_t>(u)].kind;
  auto capped = [&](IntegratorKind k) {
    PilotOptions oc = o;
    oc.max_pilot_steps = std::min(o.max_pilot_steps, std::max(1LL, pilotSteps(user, k)));
    return oc;
  };
  auto pilot = [&](IntegratorKind k) {
    pilotIntegrator(option.scenario, k, tolerance, capped(k), plan.duration, plan.short_segment, plan.whole, plan.top,
                    other);
    for (IntegratorTrial& t : other.trials) t.work_per_evaluation = work;
  };
  pilot(first);
  boundModelGap(user, other, duration, m);
  m.admitted = m.gap <= kModelShare * tolerance;
  if (m.admitted) {
    for (IntegratorKind k : o.integrators) {
      if (k == first || !offered(k)) continue;
      // what it could be chosen against: the scene's trials, and its model's so far (with its gap)
      std::vector<IntegratorTrial> known = c.trials;
      for (const IntegratorTrial& t : other.trials) {
        known.push_back(t);
        known.back().model_gap = m.gap;
      }
      if (!ruledOut(option.scenario, k, plan.top, work, known, tolerance, o, other)) pilot(k);
    }
    boundModelGap(user, other, duration, m);  // the most accurate run may be another's now
  }
  m.admitted = m.gap <= kModelShare * tolerance;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "its converged solution within %.3g of the scene's as written (runs %.3g apart, their errors "
                "%.3g and %.3g)",
                m.gap, m.difference, m.user_error, m.own_error);
  m.verdict = std::string(m.admitted ? "admitted: " : "kept out: ") + buf +
              (m.admitted ? "" : ", more than " + fmt(kModelShare) + " of the tolerance");
  m.trials = other.trials;
  c.models.push_back(m);
  if (!m.admitted) return;
  for (IntegratorTrial& t : other.trials) {
    t.model = static_cast<int>(c.models.size());
    t.model_gap = m.gap;
    c.trials.push_back(t);
  }
}

// The live estimate's windows calibrated on the pilot's own run at the
// chosen step (the finest pilot step's below them): the pilot's error
// there over the windows' reading, at most 1.
double windowScale(const IntegratorTrial& t, double dt, double duration) {
  size_t k = t.level_dt.size() - 1;  // below the pilot's steps: the finest one's ratio
  for (size_t j = 0; j < t.level_dt.size(); ++j)
    if (std::abs(dt / t.level_dt[j] - 1.0) < 1e-9) k = j;
  const double w = k < t.level_windows.size() ? t.level_windows[k] : -1.0;
  // the error over the pilot's segment, as the windows read it there
  const double grown = std::pow(std::max(1.0, duration / std::max(t.segment, 1e-9)), t.growth);
  const double e = t.level_error.empty() ? 0.0 : t.level_error[k] / grown;
  return w > 0.0 && std::isfinite(e) ? std::min(1.0, e / w) : 1.0;
}

// What the choice says of the pick, and the scenario it runs.
void describePick(const Pick& p, const scenario::Scenario& s, const std::vector<ModelOption>& options, Choice& c) {
  const IntegratorTrial& t = *p.trial;
  c.meets = p.meets;
  c.pilot_duration = t.segment;
  c.integrator = t.kind;
  c.dt = p.dt;
  c.order = nominalOrder(t.kind);
  c.observed_order = t.order;
  c.growth = t.growth;
  c.predicted_error = t.error(p.dt);
  // a refinement doubles the substeps of each step: the adaptive method's
  // error follows its local tolerance, not its output step, so nothing is
  // predicted of one there
  for (int k = 0; k <= 6; ++k) c.refined_error.push_back(t.adaptive() ? c.predicted_error : t.error(std::ldexp(p.dt, -k)));
  c.predicted_cost = t.cost(p.dt);
  c.predicted_work = t.cost(p.dt) * t.work_per_evaluation;
  c.model = t.model;
  c.model_gap = t.model_gap;
  c.window_scale = windowScale(t, p.dt, s.duration);
  // said where it matters: a step at the finest pilot run, whose error is the fit's word
  if (!t.clean_fit && p.dt <= t.level_dt.back() * (1 + 1e-9))
    c.caveat = "its error law is not clean (observed order " + fmt(t.raw_order) + ", nominal " +
               std::to_string(nominalOrder(t.kind)) + "): nothing is credited below its finest pilot step " +
               fmt(t.level_dt.back()) + " s";
  c.contact_substeps = t.contact_substeps;
  if (t.adaptive()) {  // the pseudo-step is a local tolerance; the step is the output step
    c.local_tolerance = IntegratorTrial::localTolerance(p.dt);
    c.dt = t.output_dt;
    if (!t.clean_fit && p.dt <= t.level_dt.back() * (1 + 1e-9))
      c.caveat = "its error law is not clean (observed order " + fmt(t.raw_order) +
                 " in tau^(1/3), nominal 3): nothing is credited below its finest pilot tolerance " +
                 fmt(IntegratorTrial::localTolerance(t.level_dt.back()));
  }
  const scenario::Scenario& model = c.model > 0 ? options[static_cast<size_t>(c.model - 1)].scenario : s;
  c.scenario = withSettings(model, c.integrator, c.dt, c.contact_substeps, c.local_tolerance);
}

}  // namespace

namespace {

// One pilot over plan's segment: the scene's integrators (each one that
// could still be chosen), the cheaper models, the pick; what it took.
Choice pilotOver(const scenario::Scenario& s, double tolerance, const PilotOptions& o, const PilotPlan& plan) {
  Choice c;
  c.tolerance = tolerance;
  c.pilot_duration = plan.duration;
  ModelPilot user;
  const double user_work = workPerEvaluation(s);
  PilotOptions oc = o;  // the adaptive trial's bound, from the fixed-step trials piloted before it
  for (IntegratorKind k : o.integrators) {
    if (k == IntegratorKind::Adaptive && o.max_adaptive_evaluations <= 0.0) oc.max_adaptive_evaluations = 2.0 * mostEvaluations(user);
    if (ruledOut(s, k, plan.top, user_work, user.trials, tolerance, o, user)) continue;
    pilotIntegrator(s, k, tolerance, oc, plan.duration, plan.short_segment, plan.whole, plan.top, user);
    for (IntegratorTrial& t : user.trials) t.work_per_evaluation = user_work;
  }
  c.trials = user.trials;
  // a scout pilots the scene as written alone: the models wait for the
  // pilot its choice affords
  const std::vector<ModelOption> options =
      o.other_models && !plan.scout ? modelOptions(s, o.regularized_friction) : std::vector<ModelOption>{};
  const int u = mostAccurate(user);
  for (const ModelOption& option : options) pilotModel(option, user, u, tolerance, oc, plan, s.duration, c);
  describePick(pickCheapest(c.trials, tolerance, o), s, options, c);
  c.pilot_work = pilot_detail::pilotWork(c);
  c.run_work = c.predicted_work * s.duration;
  return c;
}

}  // namespace

// The pilot: over the whole scene, or a scout and then the longest segment
// the run's predicted cost affords (PilotOptions::max_share).
Choice chooseSettings(const scenario::Scenario& s, double tolerance, const PilotOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const PilotPlan plan = pilot_detail::planPilot(s, o);
  Choice c = pilotOver(s, tolerance, o, plan);
  if (plan.scout) {
    Choice scout = std::move(c);
    const std::optional<PilotPlan> longer = pilot_detail::extendedPlan(s, o, plan, scout);
    c = longer ? pilotOver(s, tolerance, o, *longer) : std::move(scout);
    if (longer) c.pilot_work += scout.pilot_work, c.pilot_bound = scout.pilot_bound;
  }
  c.pilot_wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

std::string Choice::line() const {
  std::string out;
  if (model > 0) {
    const ModelTrial& m = models[static_cast<size_t>(model - 1)];
    out += "model " + m.name + " (" + m.what + "; " + m.verdict + ") with ";
  }
  out += std::string(integratorName(integrator)) + (local_tolerance > 0.0 ? " (local tolerance " + fmt(local_tolerance) + ")" : "") +
         " at dt " + fmt(dt) + " s" +
                    (contact_substeps > 1 ? ", contact in at least " + std::to_string(contact_substeps) + " substeps" : "") +
                    ": predicted error " +
                    fmt(predicted_error) + (model > 0 ? " incl. the model's " + fmt(model_gap) : std::string()) +
                    " (tolerance " + fmt(tolerance) + "), predicted cost " + fmt(predicted_cost) +
                    " force evaluations per sim-s" + (model > 0 ? " (" + fmt(predicted_work) + " work units)" : "");
  // the models not taken, and why: the user's model kept is a choice too
  for (size_t k = 0; k < models.size(); ++k)
    if (static_cast<int>(k) + 1 != model)
      out += "; model " + models[k].name + " not taken: " +
             (models[k].admitted ? "admitted, but not cheaper at this tolerance" : models[k].verdict);
  if (!caveat.empty()) out += "; " + caveat;
  // a pilot over part of the scene cannot see what happens after it (a
  // crash, a late manoeuvre): said where the choice is read
  if (pilot_duration < scenario.duration * (1 - 1e-9))
    out += "; piloted on the first " + fmt(pilot_duration) + " s of " + fmt(scenario.duration) +
           " s: what happens after is extrapolated" +
           (scenario.duration <= pilot_detail::kWholePilotCap ? " (\"pilot_share\": 0 pilots the whole scene)" : "");
  if (!meets) out += "; NO setting down to the finest step is predicted to meet the tolerance";
  return out;
}

std::string Choice::report() const {
  std::string out;
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "pilot: %zu integrators, %.3g s of the scene at 3 steps each, %.3g work units (the run: %.3g), %.3g s "
                "wall\n",
                trials.size(), pilot_duration, pilot_work, run_work, pilot_wall_seconds);
  out += buf;
  if (!pilot_bound.empty()) out += "  " + pilot_bound + "\n";
  for (const ModelTrial& m : models) out += "  model " + m.name + " (" + m.what + "): " + m.verdict + "\n";
  // the trials of the choice's candidates, then those of the models kept
  // out (what their pilot cost)
  std::vector<std::pair<const IntegratorTrial*, std::string>> all;
  for (const IntegratorTrial& t : trials)
    all.emplace_back(&t, t.model > 0 ? models[static_cast<size_t>(t.model - 1)].name : std::string());
  for (const ModelTrial& m : models)
    if (!m.admitted)
      for (const IntegratorTrial& t : m.trials) all.emplace_back(&t, m.name + ", kept out");
  for (const auto& [tp, label] : all) {
    const IntegratorTrial& t = *tp;
    if (!label.empty()) out += "  [" + label + "]";
    if (t.usable)
      std::snprintf(buf, sizeof buf,
                    "  %-20s dt0 %-8.3g contact substeps %d  diffs %.2e %.2e  order %.2f (%.2f)  growth %.2f  "
                    "E(h) = %.3g h^%.2f  %.3g evaluations/step\n",
                    integratorName(t.kind), t.dt0, t.contact_substeps, t.diff_coarse, t.diff_fine, t.order, t.raw_order,
                    t.growth, t.error_constant, t.order, t.step_cost);
    else
      std::snprintf(buf, sizeof buf, "  %-20s refused\n", integratorName(t.kind));
    out += buf;
    if (t.usable && t.adaptive()) {
      std::snprintf(buf, sizeof buf, "    output step %.3g s (its own error %.2e); its steps are tau^(1/3) of local tolerances tau:",
                    t.output_dt, t.tick_offset);
      out += buf;
      for (size_t k = 0; k < t.level_dt.size(); ++k) {
        std::snprintf(buf, sizeof buf, "  %.3g (%.3g evaluations/s)", IntegratorTrial::localTolerance(t.level_dt[k]),
                      k < t.level_cost.size() ? t.level_cost[k] : 0.0);
        out += buf;
      }
      out += "\n";
    }
    if (t.usable) {
      out += "    error at the pilot's steps (s: error)";
      for (size_t k = 0; k < t.level_dt.size(); ++k) {
        std::snprintf(buf, sizeof buf, "  %.3g: %.2e", t.level_dt[k], t.level_error[k]);
        out += buf;
      }
      out += "\n";
    }
    if (!t.refusal.empty()) out += "    " + t.refusal + "\n";
  }
  return out;
}

}  // namespace groundsim::accuracy
