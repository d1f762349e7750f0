// A tolerance in, settings out. A short pilot on the user's own scene runs
// each integrator that accepts it at three steps (dt0, dt0/2, dt0/4, dt0 the
// largest step of the ladder inside the scene's stability limit), fits the
// error law E(h) = C h^p from the differences (Richardson: p observed, not
// assumed), extrapolates from the pilot's segment to the whole duration by
// the error's observed growth over the segment, and counts the force
// evaluations per step (a count, not a timing: the same choice every time); the
// cheapest (integrator, step) whose predicted error, times a safety factor,
// is within the tolerance is chosen. Every refusal (an integrator the scene
// does not accept, a step that diverged in the pilot, a step beyond the
// stiffest mode's limit) is named. docs/accuracy.md, "Accuracy on demand".
#pragma once

#include <string>
#include <vector>

#include "accuracy/live_estimate.hpp"
#include "accuracy/trajectory.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::accuracy {

struct PilotOptions {
  // simulated s of the scene per trial; 0: the whole scene (up to 60 s; the
  // measure reads the final speed at its end and the largest path error
  // over all of it), falling back to fallback_duration for a trial whose
  // whole-scene runs would pass the work budget
  double pilot_duration = 0.0;
  double fallback_duration = 5.0;
  // The pilot's cost bounded by the run's (accuracy.pilot_share; no
  // pilot_duration given): a scout over the first scout_duration s
  // chooses, and predicts the run's work; the pilot is then run again over
  // the longest segment (up to the whole scene) whose work, with the
  // scout's, stays within max_share of that run's, or at least
  // min_pilot_work. A longer segment is only worth a second pilot when it
  // is at least twice the scout's; otherwise the scout's choice stands. The
  // scout pilots the scene's own models alone (model_options.hpp: the
  // cheaper ones wait for the second pilot). Off by default (max_share 0:
  // the whole scene, no scout): on the tolerance sweep's scenes run 60 s
  // at 20%, a scout cannot see a crash or a manoeuvre after its half
  // second: 23 of 31 judged choices within their tolerance, 5 more than
  // 1.5x over, up to 7.8x (docs/accuracy.md, "The pilot's cost").
  double max_share = 0.0;
  double scout_duration = 0.5;
  double min_pilot_work = 0.0;
  // the pilot refines a fit that is not clean (order off its nominal, or
  // differences that do not shrink) with finer runs, while their steps
  // stay within this many in all per integrator
  long long max_pilot_steps = 4000000;
  // work units (scenario/budget.hpp) the runs of one integrator's trial may
  // take together: a pilot is bounded like the run it prepares
  double max_work = scenario::Budget{}.max_work;
  // predicted error x safety must be within the tolerance: the prediction
  // is an extrapolation, and an error twice the prediction still meets the
  // tolerance at 1.5 only when the two differ by less than that
  double safety = 1.5;
  double min_dt = 1e-5;         // the finest step considered, s
  // also pilot the cheaper wheel and tyre models the core offers for the
  // scene's vehicles (model_options.hpp), each taken only where admitted
  bool other_models = true;
  // among them the ground's friction made regularized (accuracy.regularized_friction)
  bool regularized_friction = false;
  std::vector<IntegratorKind> integrators = {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet,
                                             IntegratorKind::Rk4, IntegratorKind::Adaptive};
  // the adaptive integrator's local tolerances tried: from the user's
  // tolerance down by 8 a level, no finer than this
  double min_local_tolerance = 1e-10;
  // and its pilot runs take at most this many force evaluations in all
  // (0: no bound): chooseSettings sets twice what the most costly of the
  // user's fixed-step trials took, so an alternative never costs the pilot
  // more than the scene's own integrators do
  double max_adaptive_evaluations = 0.0;
  int max_output_halvings = 4;  // the adaptive output step: at most top / 2^this
};

// What the pilot learnt of one integrator on the scene.
struct IntegratorTrial {
  IntegratorKind kind{};
  bool usable = false;
  std::string refusal;            // why not (when !usable), or what the pilot had to avoid
  double stability_dt = 0.0;      // largest stable step of the stiffest mode (inf: none)
  double segment = 0.0;           // simulated s of the scene its runs took
  double dt0 = 0.0;               // the coarsest step tried that stayed healthy
  double diff_coarse = 0.0;       // error measure between dt0 and dt0/2
  double diff_fine = 0.0;         // between dt0/2 and dt0/4
  double diff_before = 0.0;       // the pair before those two, when there was one (0: none)
  double order = 0.0;             // observed p (clamped)
  double growth = 0.0;            // error growth exponent over the segment
  double error_constant = 0.0;    // C of E(h) = C h^p, over the whole duration
  double step_cost = 0.0;         // force evaluations per step (deterministic: the same scene, the same choice)
  // the contact substeps floor of the family (collisions.min_substeps):
  // what contact takes at dt0, kept at every finer step so that halving the
  // step halves the contact's substep too
  int contact_substeps = 1;
  // a trial at the automatic contact substeps: the bound of its finest
  // run's error through the refined family (their finest runs' gap plus
  // that family's error), which its own differences cannot see (contact's
  // substep does not shrink with its step); it stands in for its own
  // Richardson error in each of its steps' errors (pilot.cpp)
  double contact_offset = 0.0;
  // the pilot's steps and each one's error (its difference to the next
  // finer run plus that run's error; the finest from the fit)
  std::vector<double> level_dt, level_error;
  // the live estimate's windows on each pilot run (watched as the run will
  // be), for the windows' calibration
  std::vector<double> level_windows;
  double raw_order = 0.0;         // log2 of the last two differences' ratio, unclamped
  // false: by the finest run the pilot could afford, the differences still
  // did not shrink at the integrator's order (chaotic stick-slip, a step
  // near a stability limit): the law is not extrapolated below that run,
  // whose error error(h) keeps for every finer step
  bool clean_fit = true;
  // the model it ran: 0 the user's, k > 0 Choice::models[k - 1] (a cheaper
  // wheel or tyre model); model_gap, the bound of that model's converged
  // solution's distance from the user's, is part of every error it predicts
  int model = 0;
  double model_gap = 0.0;
  // work units (scenario/budget.hpp) of one force evaluation of its model:
  // evaluations of two models compare through it
  double work_per_evaluation = 1.0;
  // the force evaluations its runs took in all (the pilot's cost)
  double pilot_evaluations = 0.0;
  // The adaptive integrator (Bogacki-Shampine 3(2), error-controlled): its
  // runs cover each output step output_dt in internal steps sized by a
  // local tolerance tau, and its "steps" above (dt0, level_dt, error(h))
  // are the pseudo-steps h = tau^(1/3): a tolerance 8 times finer is h / 2,
  // and an error proportional to tau is the order 3 of its law in h. Its
  // cost is measured per level (level_cost, force evaluations per
  // simulated s), below the pilot's finest level growing as 1 / h (a third
  // order method's steps as tau^(-1/3)). 0 / empty for a fixed step.
  double output_dt = 0.0;
  std::vector<double> level_cost;
  // What the output step itself costs the adaptive runs, whatever their
  // tolerance: a road car's controls and powertrain, and the drive and
  // brake torques, are updated once per output step, not per internal step.
  // Measured first order: twice the difference of two accurate runs at the
  // pilot's top output step and half of it, scaled to output_dt (which is
  // halved from the top until this is within a fourth of the tolerance);
  // part of every error it predicts.
  double tick_offset = 0.0;
  bool adaptive() const { return output_dt > 0.0; }
  static double localTolerance(double h) { return h * h * h; }
  // predicted over the whole duration: measured at the pilot's steps, the
  // fitted law below them, infinite above dt0; plus model_gap
  double error(double h) const;
  // force evaluations per simulated s at (pseudo-)step h
  double cost(double h) const;
};

// A cheaper model the pilot considered (model_options.hpp) and what it
// found: the bound of the distance between its converged solution and the
// user's (their most accurate pilot runs' difference plus each run's own
// error), and whether that is within the fraction of the tolerance a model
// may take (kModelShare).
struct ModelTrial {
  std::string name, what;
  double gap = 0.0;                 // the bound (infinite: not measured)
  double difference = 0.0;          // the two most accurate runs' difference
  double user_error = 0.0, own_error = 0.0;  // each of those runs' error
  bool admitted = false;            // gap within kModelShare x tolerance
  std::string verdict;              // one line: why taken, kept out or not piloted
  // its trials (the first integrator's alone when kept out), for the report;
  // admitted ones are also among Choice::trials, the choice's candidates
  std::vector<IntegratorTrial> trials;
};

// A model may take at most this share of the tolerance: its converged
// solution's distance from the user's, as bounded by the pilot.
inline constexpr double kModelShare = 1.0 / 3.0;

struct Choice {
  IntegratorKind integrator{};
  double dt = 0.0;
  double local_tolerance = 0.0;   // the adaptive integrator's (physics.tolerance); 0: a fixed step
  int order = 1;                  // the chosen integrator's nominal order (for the live estimate)
  int contact_substeps = 1;       // collisions.min_substeps of the choice
  double observed_order = 1.0;
  double growth = 0.0;            // the chosen trial's error growth exponent
  double predicted_error = 0.0;
  // the chosen trial's predicted error at dt / 2^k, k = 0 .. 6 (measured at
  // the pilot's steps, its fitted law below them): what a refinement at a
  // safe point (refinement.hpp) is predicted to make of the error
  std::vector<double> refined_error;
  double predicted_cost = 0.0;    // force evaluations per simulated s
  // the live estimate's windows calibrated on the pilot's own run at the
  // chosen step (the finest pilot step's below them): the pilot's error
  // there over the windows' reading, at most 1. The windows see the error
  // a step makes in a window and extrapolate it linearly; where that reads
  // above the error the pilot measured on the same run, their reading is
  // scaled down by as much (LiveEstimate::setWindowScale).
  double window_scale = 1.0;
  bool meets = false;             // predicted within the tolerance
  // what the prediction rests on when the chosen trial's law is not clean
  // (said in line()); empty when it is
  std::string caveat;
  double tolerance = 0.0;
  // the model chosen: 0 the user's, k > 0 models[k - 1] (its scenario runs)
  int model = 0;
  double model_gap = 0.0;         // part of predicted_error (0 with the user's model)
  // work units per simulated s (evaluations x their model's work): the cost
  // that compares models; predicted_cost is in the chosen model's evaluations
  double predicted_work = 0.0;
  std::vector<ModelTrial> models; // the cheaper models considered
  std::vector<IntegratorTrial> trials;
  double pilot_duration = 0.0;    // simulated s per trial run (the chosen trial's)
  double pilot_wall_seconds = 0.0;
  // work units (scenario/budget.hpp): what the pilot's runs took (the
  // scout's included), and what the run is predicted to take
  // (predicted_work over the scene's duration): counts, not timings
  double pilot_work = 0.0;
  double run_work = 0.0;
  // how the pilot's segment was chosen, one line: the scout and the bound
  // (empty: the segment was given, or the scene is short enough to pilot whole)
  std::string pilot_bound;
  bool from_cache = false;        // made before for the same content (choice_cache.hpp): no pilot ran
  // s with the chosen settings (its document says so; its `accuracy` kept)
  scenario::Scenario scenario;
  // one line: "velocity_verlet at dt 0.001 s: predicted error 2.1e-04 (tolerance 0.01), predicted cost 2000 force
  // evaluations per sim-s"
  std::string line() const;
  // what the live estimate is given of it (LiveEstimate::expect)
  Prediction prediction() const { return {predicted_error, growth, window_scale, refined_error}; }
  // the table of trials, one line each, for --verbose output and docs
  std::string report() const;
};

// Richardson on three runs at h, h/2, h/4 whose error measures between
// neighbours are d_coarse (h against h/2) and d_fine (h/2 against h/4):
// the observed order p = log2(d_coarse / d_fine) and the error of the
// finest run, d_fine / (2^p - 1). Differences that do not shrink give the
// order 0.5 and the larger difference (pessimistic); differences that
// shrink by more than half an order faster than the integrator's nominal
// order (a coarse run outside the asymptotic range) give the order 1, the
// lowest: one difference says nothing of the order.
struct ErrorFit {
  double order = 0.0;
  double e_fine = 0.0;  // error of the finest run
};
ErrorFit fitErrorLaw(double d_coarse, double d_fine, int nominal);

// The options a scenario's `accuracy` section and a budget give.
PilotOptions pilotOptions(const scenario::AccuracySpec& a, const scenario::Budget& budget);

// The largest step of the ladder (0.02 s / 2^k) at or below h.
double ladderStepAtMost(double h);
// The integrator's nominal order on smooth problems.
int nominalOrder(IntegratorKind kind);

// Chooses for s, whose own settings (integrator, dt) are ignored. Its
// models (wheels, tyres, friction) are kept unless a cheaper one the core
// offers (model_options.hpp) is admitted: its converged solution bounded
// within kModelShare of the tolerance of the user's, and its cheapest
// setting, with that bound added to its predicted error, cheaper in work
// than the user's model's. Throws ScenarioError when no
// integrator can run the scene at all, naming each one's reason.
Choice chooseSettings(const scenario::Scenario& s, double tolerance, const PilotOptions& o = {});

}  // namespace groundsim::accuracy
