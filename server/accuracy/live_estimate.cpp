#include "accuracy/live_estimate.hpp"

#include <algorithm>
#include <cmath>

#include "accuracy/error_measure.hpp"
#include "physics/checks/telemetry.hpp"

namespace groundsim::accuracy {

LiveEstimate::LiveEstimate(const scenario::Scenario& s, int order, LiveEstimateOptions o) {
  dt_ = s.options.dt;
  const double p2 = std::pow(2.0, order);
  factor_ = p2 / (p2 - 1.0);
  order_factor_ = 1.0 / p2;
  run_duration_ = o.duration;
  const double window = o.duration > 0.0 ? std::min(o.window, o.duration / (4.0 * o.every)) : o.window;
  window_steps_ = std::max(8LL, std::llround(window / dt_));
  every_ = std::max(2, o.every);
  // the shadow: the same scenario at half the step, its own scene (the
  // step-dependent parts of the model, e.g. object substeps, follow dt)
  scenario::Scenario half = s;
  half.options.dt = dt_ / 2;
  scene_ = std::make_unique<scenario::Scene>(scenario::buildScene(half));
  shadow_ = std::make_unique<Simulator>(scene_->built.model, scene_->built.initial);
  for (const CarHandle& car : scene_->cars) vehicles_.push_back(car.vehicle);
  sum_p_.assign(vehicles_.size(), 0.0);
  sum_v_.assign(vehicles_.size(), 0.0);
  base_p_.assign(vehicles_.size(), 0.0);
  distance_.assign(vehicles_.size(), 0.0);
  speed_now_.assign(vehicles_.size(), 0.0);
}

LiveEstimate::~LiveEstimate() = default;

void LiveEstimate::beforeStep(const Simulator& main) {
  const long long tick = main.state().tick;
  if (tick % window_steps_ != 0) return;
  update(main);  // distance travelled, at every window boundary
  if (active_ || failed_) return;
  if (force_window_) {
    startWindow(main);
    skip_next_ = true;  // in place of the next scheduled one: the cost stays 2 / every
  } else if ((tick / window_steps_) % every_ == 0) {
    if (skip_next_) skip_next_ = false;
    else startWindow(main);
  }
}

void LiveEstimate::startWindow(const Simulator& main) {
  State s = main.state();
  s.tick *= 2;  // the same time at half the step
  shadow_->restore(s);
  active_ = true;
  force_window_ = false;
  window_end_ = main.state().tick + window_steps_;
}

void LiveEstimate::afterStep(const Simulator& main) {
  if (!active_) return;
  if (!main.healthy()) {
    active_ = false;
    return;
  }
  // the commands the main step used: the wheels' and the road cars'
  shadow_->controls() = main.state().controls;
  for (size_t c = 0; c < main.state().car_controls.size(); ++c)
    shadow_->setCarControls(static_cast<int>(c), main.state().car_controls[c]);
  const bool ok = shadow_->step(2);
  shadow_steps_ += 2;
  if (!ok) {
    active_ = false;
    failed_ = true;
    return;
  }
  if (main.state().tick >= window_end_) endWindow(main);
}

void LiveEstimate::endWindow(const Simulator& main) {
  active_ = false;
  for (size_t i = 0; i < vehicles_.size(); ++i) {
    const VehicleSample a = sampleVehicle(main, vehicles_[i], false);
    const VehicleSample b = sampleVehicle(*shadow_, vehicles_[i], false);
    sum_p_[i] += factor_ * (a.position - b.position).norm();
    sum_v_[i] += factor_ * std::abs(a.velocity.norm() - b.velocity.norm());
  }
  sampled_time_ += static_cast<double>(window_steps_) * dt_;
  ++windows_;
  ++windows_total_;
  update(main);
}

void LiveEstimate::reset() {
  active_ = failed_ = false;
  std::fill(sum_p_.begin(), sum_p_.end(), 0.0);
  std::fill(sum_v_.begin(), sum_v_.end(), 0.0);
  std::fill(base_p_.begin(), base_p_.end(), 0.0);
  std::fill(distance_.begin(), distance_.end(), 0.0);
  std::fill(speed_now_.begin(), speed_now_.end(), 0.0);
  last_pos_.clear();
  sampled_time_ = 0.0;
  windows_ = windows_total_ = 0;
  estimate_ = path_ = speed_ = 0.0;
  level_ = refinements_ > 0 ? -1.0 : 0.0;
  // the run starts again at its current (refined) setting
  segment_t0_ = speed_before_ = 0.0;
  force_window_ = skip_next_ = false;
  prediction_base_ = prediction_t0_ = 0.0;
}

void LiveEstimate::refine(int substeps, double t) {
  // the path error made so far, at the rate the windows measured
  if (sampled_time_ > 0.0)
    for (size_t i = 0; i < vehicles_.size(); ++i) base_p_[i] += sum_p_[i] / sampled_time_ * (t - segment_t0_);
  speed_before_ = speed_;
  std::fill(sum_p_.begin(), sum_p_.end(), 0.0);
  std::fill(sum_v_.begin(), sum_v_.end(), 0.0);
  sampled_time_ = 0.0;
  windows_ = 0;
  segment_t0_ = t;
  prediction_base_ = predicted(t);
  prediction_t0_ = t;
  ++refinements_;
  const auto k = static_cast<size_t>(refinements_);
  if (k < refined_error_.size() && refined_error_[0] > 0.0 && std::isfinite(refined_error_[k]))
    prediction_scale_ = refined_error_[k] / refined_error_[0];  // as the pilot measured the finer steps
  else
    prediction_scale_ *= order_factor_;
  level_ = -1.0;
  // a window under way compared the coarser main run: dropped, and the
  // finer setting measured from the next boundary on
  active_ = false;
  force_window_ = !failed_;
  shadow_->refine(substeps);
}

void LiveEstimate::setPrediction(double error, double duration, double growth) {
  prediction_ = error;
  prediction_duration_ = duration;
  prediction_growth_ = growth;
}

double LiveEstimate::predictedRaw(double t) const {
  if (!(prediction_ > 0.0) || !(prediction_duration_ > 0.0) || !(t > 0.0)) return 0.0;
  return prediction_ * std::pow(std::min(t / prediction_duration_, 1e6), prediction_growth_);
}

double LiveEstimate::predicted(double t) const {
  if (refinements_ == 0) return predictedRaw(t);
  return prediction_base_ + prediction_scale_ * std::max(0.0, predictedRaw(t) - predictedRaw(prediction_t0_));
}

void LiveEstimate::update(const Simulator& main) {
  const bool first = last_pos_.empty();
  if (first) last_pos_.resize(vehicles_.size());
  for (size_t i = 0; i < vehicles_.size(); ++i) {
    const VehicleSample a = sampleVehicle(main, vehicles_[i], false);
    if (!first) distance_[i] += (a.position - last_pos_[i]).norm();
    last_pos_[i] = a.position;
    speed_now_[i] = a.velocity.norm();
  }
  const double t = main.state().t;
  if (sampled_time_ <= 0.0) {
    // before the first window of this setting: what was made before it
    path_ = 0.0;
    for (size_t i = 0; i < vehicles_.size(); ++i)
      path_ = std::max(path_, base_p_[i] / std::max(distance_[i], kMinDistance));
    speed_ = speed_before_ * order_factor_;
    estimate_ = std::max({window_scale_ * path_, window_scale_ * speed_, predicted(t)});
    if (refinements_ == 0) level_ = predictedLevel(t);
    return;
  }
  path_ = speed_ = 0.0;
  double level_path = 0.0;
  // the level looks at the run's end (a run of known length): the error
  // at the setting's rate by then over the distance travelled by then, at
  // the speed of now (a launch's distance grows faster than its time)
  const double horizon = std::max(t, run_duration_);
  for (size_t i = 0; i < vehicles_.size(); ++i) {
    const double rate_p = sum_p_[i] / sampled_time_;
    const double d = std::max(distance_[i], kMinDistance);
    path_ = std::max(path_, (base_p_[i] + rate_p * (t - segment_t0_)) / d);
    const double d_end = std::max(distance_[i] + speed_now_[i] * (horizon - t), kMinDistance);
    level_path = std::max(level_path, rate_p * horizon / d_end);
    // a speed error does not pile up window on window (grip, drive and
    // brakes pull the speed back): the mean made in one window
    speed_ = std::max(speed_, sum_v_[i] / windows_ / std::max(speed_now_[i], kMinSpeed));
  }
  estimate_ = std::max({window_scale_ * path_, window_scale_ * speed_, predicted(t)});
  // the windows decide once two of this setting agree that it errs: the
  // first window of a run starts from rest, where a launch's speed error
  // over a speed near the floor reads high (the sedan's launch read 1e-3
  // after 0.16 s with 6e-4 made over the run)
  const double windows = windows_ >= 2 ? window_scale_ * std::max(level_path, speed_) : 0.0;
  level_ = std::max(windows, predictedLevel(t));
}

double LiveEstimate::predictedLevel(double t) const {
  // a run of known length: the pilot's figure for its whole length (the
  // error it predicts at the end, at the current setting); a session
  // without end: at the time reached
  return prediction_scale_ * predictedRaw(std::max(t, run_duration_));
}

bool stepWatched(const scenario::Scene& scene, Simulator& sim, long long n, LiveEstimate* live) {
  if (!live) return scenario::stepScene(scene, sim, n);
  for (long long i = 0; i < n; ++i) {
    live->beforeStep(sim);
    if (!scenario::stepScene(scene, sim, 1)) return false;
    live->afterStep(sim);
  }
  return true;
}

}  // namespace groundsim::accuracy
