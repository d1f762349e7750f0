// The live error estimate: while a run or session goes, a shadow copy of the
// simulation is stepped at half the step, in lockstep with the same
// commands, over sampled windows (one window in `every`, the first at t = 0).
// At a window's end the difference between the two, times 2^p / (2^p - 1)
// (Richardson, p the integrator's order), is the error the main run made in
// that window: a position error and a speed error per vehicle. The position
// errors' rate over the sampled windows stands for the whole run (the path
// error at time t is rate t, relative to the distance travelled); the speed
// error is the mean made in one window (grip and drive pull a speed back,
// so it does not pile up), relative to the speed. Windows see the error a
// step makes locally, not what an impact between two windows amplifies: a
// run whose settings came from a pilot (pilot.hpp) also carries the pilot's
// measured global error, scaled to the time elapsed by its growth, and the
// estimate is the larger of the two. Cost: two shadow steps per main step in
// one window of `every`, so 2 / every of the run (12.5% at 16).
// docs/accuracy.md, "The live estimate".
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::accuracy {

struct LiveEstimateOptions {
  double window = 0.25;   // simulated s per window (at least 8 steps)
  int every = 16;         // one window sampled in this many
  // a run of known length: windows short enough that four are sampled
  // (0: a session without end, windows of `window`)
  double duration = 0.0;
};

// What a pilot predicted for the run (pilot.hpp, Choice::prediction()).
struct Prediction {
  double error = 0.0;         // at the run's duration
  double growth = 0.0;        // error ~ t^growth
  double window_scale = 1.0;  // the windows' calibration
  std::vector<double> refined_error;  // at dt / 2^k, k = 0, 1, ...
};

class LiveEstimate {
 public:
  // s: the scenario the main run steps (its dt); order: its integrator's.
  LiveEstimate(const scenario::Scenario& s, int order, LiveEstimateOptions o = {});
  ~LiveEstimate();
  LiveEstimate(const LiveEstimate&) = delete;
  LiveEstimate& operator=(const LiveEstimate&) = delete;

  // Around each step of the main simulator (the commands it steps with are
  // read after the step and given to the shadow).
  void beforeStep(const Simulator& main);
  void afterStep(const Simulator& main);

  // Forgets what it measured: the run starts again (a session's reset).
  void reset();

  // The main run was refined to `substeps` integrator steps per step at
  // its time t (Simulator::refine; refinement.hpp). The error made so far
  // stays in the estimate; from here on the windows measure the finer
  // setting (the shadow refines with it, to half its step), the first at
  // the next window boundary, and the pilot's prediction grows 2^-p as
  // fast. The estimate of the finer setting alone is level().
  void refine(int substeps, double t);

  // The pilot's prediction for the whole run (error at `duration`, growing
  // as t^growth): a floor of the estimate (0: none).
  void setPrediction(double error, double duration, double growth);

  // The pilot's prediction at dt / 2^k (Choice::refined_error): after k
  // refinements the prediction is scaled by e[k] / e[0] rather than 2^-pk.
  void setRefinedPredictions(std::vector<double> e) { refined_error_ = std::move(e); }

  // All of a pilot's prediction, for a scene of `duration` s: the three above.
  void expect(const Prediction& p, double duration) {
    setPrediction(p.error, duration, p.growth);
    setWindowScale(p.window_scale);
    setRefinedPredictions(p.refined_error);
  }

  // The windows' calibration (Choice::window_scale, at most 1): their
  // reading is scaled by it before it is compared with the prediction.
  void setWindowScale(double scale) { window_scale_ = scale > 0.0 ? scale : 1.0; }

  // The estimated error of the run so far (the error measure's value), 0
  // before the first window ends.
  double estimate() const { return estimate_; }
  double pathEstimate() const { return path_; }
  double speedEstimate() const { return speed_; }
  // The error the current setting would make over the run (as estimate()
  // if the whole run had taken it): what a refinement is decided on. The
  // larger of the windows' reading, once two windows of the setting have
  // ended, and the pilot's prediction for the run's whole length, scaled
  // by 2^-p per refinement. Below 0 while it is unknown (no window has
  // ended since the last refinement).
  double level() const { return level_; }
  int refinements() const { return refinements_; }
  // windows ended since the last refinement (the run's start)
  int settingWindows() const { return windows_; }
  // Shadow steps taken (each half a main step's cost).
  long long shadowSteps() const { return shadow_steps_; }
  int windowsMeasured() const { return windows_total_; }
  // The shadow diverged at half the step while the main did not: the
  // estimate stops there (the last value holds).
  bool shadowFailed() const { return failed_; }

 private:
  void startWindow(const Simulator& main);
  void endWindow(const Simulator& main);
  void update(const Simulator& main);
  double predicted(double t) const;       // the pilot's figure at t, refinements included
  double predictedRaw(double t) const;    // at the pilot's setting
  double predictedLevel(double t) const;  // the current setting's, for the run's whole length

  std::unique_ptr<scenario::Scene> scene_;  // the shadow's (dt / 2)
  std::unique_ptr<Simulator> shadow_;
  double factor_ = 1.0;    // 2^p / (2^p - 1)
  long long window_steps_ = 8;
  int every_ = 16;
  double dt_ = 0.0;
  bool active_ = false, failed_ = false;
  long long window_end_ = 0;
  std::vector<int> vehicles_;
  // per vehicle, over the windows sampled since the last refinement (the
  // current setting's); base_p_: the path error made before it (m)
  std::vector<double> sum_p_, sum_v_, base_p_;
  double segment_t0_ = 0.0;     // s: when the current setting began
  double speed_before_ = 0.0;   // the speed error's reading before the last refinement
  bool force_window_ = false;   // a window at the next boundary (after a refinement)
  bool skip_next_ = false;      // ... in place of the next scheduled window
  int refinements_ = 0;
  double level_ = 0.0;
  double run_duration_ = 0.0;   // LiveEstimateOptions::duration
  std::vector<double> refined_error_;
  double order_factor_ = 0.5;   // 2^-p: a refinement's effect on the error rate
  // the pilot's prediction after refinements: its value at the last one
  // plus what it grows since, times order_factor_^refinements_
  double prediction_base_ = 0.0, prediction_t0_ = 0.0, prediction_scale_ = 1.0;
  std::vector<Vec3> last_pos_;
  std::vector<double> distance_, speed_now_;
  double sampled_time_ = 0.0;
  long long shadow_steps_ = 0;
  int windows_ = 0;        // since the last refinement
  int windows_total_ = 0;
  double estimate_ = 0.0, path_ = 0.0, speed_ = 0.0;
  double prediction_ = 0.0, prediction_duration_ = 0.0, prediction_growth_ = 0.0;
  double window_scale_ = 1.0;
};

// n steps of the scene, each watched by `live` when there is one (the same
// run: the estimate only reads it); false when the simulation diverged.
bool stepWatched(const scenario::Scene& scene, Simulator& sim, long long n, LiveEstimate* live);

}  // namespace groundsim::accuracy
