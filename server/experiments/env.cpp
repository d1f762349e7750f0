// One environment: reset (draws, initial state), step (action, physics,
// reward, flags), observation, save and load. Definitions of every feature
// and reward term: docs/scenario.md, "Tasks".
#include "experiments/env.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "experiments/task_context.hpp"
#include "physics/kernels/batch_step.hpp"

namespace groundsim::experiments {
namespace {

using scenario::ActionKind;
using scenario::Feature;
using scenario::TaskSpec;

constexpr double kDeg = std::numbers::pi / 180.0;

// Body-to-world rotation of body b.
Mat3 rotation(const Eigen::VectorXd& y, int b) { return bodyRot(y, b).normalized().toRotationMatrix(); }

float toFloat(double v) {
  if (!std::isfinite(v)) return 0.0f;  // never published (only a diverged step's workspace could hold one)
  constexpr double most = std::numeric_limits<float>::max();
  return static_cast<float>(std::clamp(v, -most, most));
}

}  // namespace

Env::Env(std::shared_ptr<const TaskContext> ctx, std::uint64_t seed) : ctx_(std::move(ctx)) {
  const Layout& l = ctx_->layout;
  action_.assign(static_cast<size_t>(l.actionSize()), 0.0f);
  previous_ = action_;
  last_obs_.assign(static_cast<size_t>(l.obsSize()), 0.0f);
  feature_.assign(static_cast<size_t>(l.obsSize()), 0.0);
  ranges_ = ctx_->task().randomize;
  sim_ = std::make_unique<Simulator>(ctx_->scene.built.model, ctx_->scene.built.initial);
  probe_ = std::make_unique<GroundProbe>(*sim_->model().ground);
  sensors_ = resolveSensors(*ctx_, sim_->model());
  reset(seed, last_obs_.data());
  // the first step() begins episode 1 (its action ignored), as after any end
  episode_ = 0;
  needs_reset_ = true;
}

State Env::initialState(std::shared_ptr<const Model>* model) const {
  const bool moved = drawn_[kDrawnX] != 0.0 || drawn_[kDrawnY] != 0.0 || drawn_[kDrawnYaw] != 0.0 ||
                     drawn_[kDrawnSpeed] != 0.0;
  const std::vector<scenario::ParameterRange>& parameters = ranges_.parameters;
  if (parameters.empty() && !moved) {
    *model = ctx_->scene.built.model;
    return ctx_->scene.built.initial;
  }
  scenario::Scenario s;
  if (!parameters.empty()) {
    nlohmann::json doc = ctx_->base_document;
    for (size_t i = 0; i < parameters.size(); ++i)
      scenario::applyOverride(doc, overrideText(parameters[i].path, drawn_[kDrawnParameters + i]), ctx_->budget);
    s = scenario::parseScenario(std::move(doc), ctx_->budget, ctx_->files);
  } else {
    s.options = ctx_->scenario.options;
    s.ground = ctx_->scenario.ground;
    s.vehicles = ctx_->scenario.vehicles;
    s.document = nlohmann::json::object();
  }
  CarPlacement& at = s.vehicles.at(static_cast<size_t>(ctx_->vehicle)).placement;
  at.position.x() += drawn_[kDrawnX];
  at.position.y() += drawn_[kDrawnY];
  at.yaw += drawn_[kDrawnYaw];
  at.speed += drawn_[kDrawnSpeed];
  scenario::Scene scene = scenario::buildScene(s);
  // only a drawn parameter changes the model: placements share the base one
  *model = parameters.empty() ? ctx_->scene.built.model : scene.built.model;
  return std::move(scene.built.initial);
}

void Env::reset(std::optional<std::uint64_t> seed, float* obs) {
  if (seed) rng_.seed(*seed);
  const scenario::Randomization& r = ranges_;
  drawn_.resize(kDrawnParameters + r.parameters.size());
  // always four draws for the placement, then one per parameter: a task's
  // stream does not depend on which ranges are empty
  drawn_[kDrawnX] = rng_.uniform(r.x[0], r.x[1]);
  drawn_[kDrawnY] = rng_.uniform(r.y[0], r.y[1]);
  drawn_[kDrawnYaw] = rng_.uniform(r.yaw_deg[0], r.yaw_deg[1]) * kDeg;
  drawn_[kDrawnSpeed] = rng_.uniform(r.speed[0], r.speed[1]);
  for (size_t i = 0; i < r.parameters.size(); ++i)
    drawn_[kDrawnParameters + i] = rng_.uniform(r.parameters[i].lo, r.parameters[i].hi);
  std::shared_ptr<const Model> model;
  State s = initialState(&model);
  // the agent drives its vehicle from rest: no scripted drive of the scene
  const int rc = ctx_->road_car;
  if (rc >= 0) {
    s.car_controls.at(static_cast<size_t>(rc)) = CarControls{};
  } else {
    for (int w : ctx_->wheels)
      if (w >= 0) s.controls.at(static_cast<size_t>(w)).drive_torque = 0.0;
  }
  if (model != sim_->modelPtr()) {
    sim_ = std::make_unique<Simulator>(model, std::move(s));
    probe_ = std::make_unique<GroundProbe>(*sim_->model().ground);
    sensors_ = resolveSensors(*ctx_, sim_->model());
  } else {
    sim_->restore(s);
  }
  begin(obs);
}

void Env::begin(float* obs) {
  ++episode_;
  steps_ = 0;
  return_ = 0.0;
  diverged_ = false;
  needs_reset_ = false;
  std::fill(previous_.begin(), previous_.end(), 0.0f);
  std::fill(action_.begin(), action_.end(), 0.0f);
  observe(obs);
}

void Env::setAction(const float* a) {
  const Layout& l = ctx_->layout;
  for (size_t k = 0; k < action_.size(); ++k) action_[k] = std::clamp(a[k], l.action_low[k], l.action_high[k]);
}

void Env::applyAction() {
  const TaskSpec& t = ctx_->task();
  const int rc = ctx_->road_car;
  if (t.action == ActionKind::CarControls) {
    CarControls c = sim_->carControls(rc);
    c.throttle = action_[0];
    c.brake = action_[1];
    c.steer = action_[2];
    c.handbrake = t.handbrake && action_[3] > 0.5f;
    sim_->setCarControls(rc, c);
  } else if (rc >= 0) {
    CarControls c = sim_->carControls(rc);
    for (int w = 0; w < 4; ++w) c.wheel_torque[static_cast<size_t>(w)] = action_[static_cast<size_t>(w)];
    sim_->setCarControls(rc, c);
  } else {
    for (int w = 0; w < 4; ++w)
      if (ctx_->wheels[static_cast<size_t>(w)] >= 0)
        sim_->controls()[static_cast<size_t>(ctx_->wheels[static_cast<size_t>(w)])].drive_torque =
            action_[static_cast<size_t>(w)];
  }
}

bool stepsBatched(const TaskContext& c) {
  const scenario::TaskSpec& t = c.task();
  if (!t.randomize.parameters.empty() || BatchStep::unsupported(*c.scene.built.model) != nullptr) return false;
  for (scenario::Feature f : t.observation)
    if (f == scenario::Feature::WheelContact || f == scenario::Feature::WheelSlip) return false;
  return true;
}

void Env::step(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated) {
  if (!beginStep(obs, reward, terminated, truncated)) return;
  bool ok = true;
  const bool bumps = ctx_->task().reward.collision != 0.0 && sim_->model().collisions;
  for (int k = 0; k < ctx_->task().control_period && ok; ++k) {
    ok = sim_->step();
    if (bumps) addBump();
  }
  finishStep(obs, reward, terminated, truncated);
}

// The hits of the task's vehicle this step, as the velocity change they
// give it: |force| dt / its mass (a reward term that means the same for a
// 1.4 kg car and a 1.5 t one).
void Env::addBump() {
  const Model& m = sim_->model();
  const int vehicle = ctx_->task().vehicle;
  for (const Hit& h : sim_->hits()) {
    const CollisionGroup& a = m.groups[h.a];
    const CollisionGroup& b = m.groups[h.b];
    const CollisionGroup* mine = a.vehicle == vehicle ? &a : b.vehicle == vehicle ? &b : nullptr;
    if (mine && mine->mass > 0.0) bump_ += h.force.norm() * m.opt.dt / mine->mass;
  }
}

bool Env::beginStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated) {
  if (needs_reset_) {
    reset(std::nullopt, obs);
    *reward = 0.0;
    *terminated = *truncated = 0;
    return false;
  }
  before_ = bodyPos(sim_->state().y, ctx_->body);
  bump_ = 0.0;
  applyAction();
  return true;
}

void Env::finishStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated) {
  const TaskSpec& t = ctx_->task();
  const int b = ctx_->body;
  const Vec3 before = before_;
  const double gx = t.goal[0], gy = t.goal[1];
  const double dist_before = std::hypot(gx - before.x(), gy - before.y());
  diverged_ = !sim_->healthy();

  const Eigen::VectorXd& y = sim_->state().y;
  const Vec3 c = bodyPos(y, b);
  const Mat3 R = rotation(y, b);
  const double dist = std::hypot(gx - c.x(), gy - c.y());
  const double up_z = std::clamp(R(2, 2), -1.0, 1.0);
  const bool at_goal = t.goal_radius > 0.0 && dist <= t.goal_radius;

  // reward terms (docs/scenario.md): each finite by construction, the
  // actions normalised to [-1, 1] by their bounds' largest magnitude
  const Layout& l = ctx_->layout;
  double effort = 0.0, jerk = 0.0;
  for (size_t k = 0; k < action_.size(); ++k) {
    const double scale = std::max(std::abs(l.action_low[k]), std::abs(l.action_high[k]));
    const double a = action_[k] / scale, p = previous_[k] / scale;
    effort += a * a;
    jerk += (a - p) * (a - p);
  }
  const double n = static_cast<double>(std::max<size_t>(action_.size(), 1));
  const double v_forward = (R.transpose() * Vec3(bodyVel(y, b))).x();
  const double dv = (v_forward - t.target_speed) / t.speed_tolerance;
  const scenario::RewardWeights& w = t.reward;
  double r = 0.0;
  if (w.progress_to_goal != 0.0) r += w.progress_to_goal * (dist_before - dist);
  if (w.progress_along != 0.0)
    r += w.progress_along * ((c.x() - before.x()) * t.direction[0] + (c.y() - before.y()) * t.direction[1]);
  if (w.speed_tracking != 0.0) r += w.speed_tracking * std::exp(-dv * dv);
  if (w.effort != 0.0) r -= w.effort * effort / n;
  if (w.jerk != 0.0) r -= w.jerk * jerk / n;
  if (w.tilt != 0.0) r -= w.tilt * (1.0 - up_z);
  if (w.collision != 0.0) r -= w.collision * bump_;
  r += w.alive;
  if (at_goal) r += w.goal;
  if (!std::isfinite(r)) r = 0.0;

  bool term = diverged_ || at_goal;
  if (t.max_tilt_deg > 0.0 && std::acos(up_z) > t.max_tilt_deg * kDeg) term = true;
  if (t.has_region && (c.x() < t.region_min[0] || c.x() > t.region_max[0] || c.y() < t.region_min[1] ||
                       c.y() > t.region_max[1]))
    term = true;
  ++steps_;
  const bool trunc = !term && ctx_->max_steps > 0 && steps_ >= ctx_->max_steps;
  return_ += r;
  previous_ = action_;  // same size: no allocation
  observe(obs);
  *reward = r;
  *terminated = term ? 1 : 0;
  *truncated = trunc ? 1 : 0;
  needs_reset_ = term || trunc;
}

void Env::observe(float* obs) {
  SensorInputs in;
  in.probe = probe_.get();
  in.previous_action = previous_.data();
  in.time = static_cast<double>(steps_) * ctx_->control_dt;
  in.fresh = steps_ == 0;  // nothing has touched the ground yet this episode
  readSensors(sensors_, *ctx_, sim_->model(), sim_->state(), sim_->workspace(), in, feature_.data());
  for (size_t i = 0; i < feature_.size(); ++i) last_obs_[i] = toFloat(feature_[i]);
  if (obs != last_obs_.data()) std::copy(last_obs_.begin(), last_obs_.end(), obs);
}

EnvInfo Env::info() const {
  EnvInfo i;
  i.episode = episode_;
  i.episode_steps = steps_;
  i.episode_return = return_;
  i.diverged = diverged_;
  return i;
}

EnvSnapshot Env::save() const {
  EnvSnapshot s;
  s.state = sim_->state();
  s.rng = rng_.state();
  s.episode = episode_;
  s.episode_steps = steps_;
  s.episode_return = return_;
  s.diverged = diverged_;
  s.needs_reset = needs_reset_;
  s.previous_action = previous_;
  s.drawn = drawn_;
  s.ranges = rangesJson(ranges_).dump();
  s.observation = last_obs_;
  return s;
}

void Env::load(const EnvSnapshot& s, float* obs) {
  auto bad = [](const std::string& why) { throw ExperimentError("snapshot", why); };
  // the snapshot's ranges, checked as a curriculum's (a snapshot's checksum
  // guards against corruption, not against a crafted file)
  scenario::Randomization ranges;
  try {
    ranges = curriculumRanges(*ctx_, s.ranges, ctx_->task().randomize);
  } catch (const scenario::ScenarioError& e) {
    bad("its randomisation ranges do not fit this task: " + e.lines("; "));
  }
  const size_t nparams = ranges.parameters.size();
  if (s.drawn.size() != kDrawnParameters + nparams)
    bad(std::to_string(s.drawn.size()) + " drawn values, this task draws " + std::to_string(kDrawnParameters + nparams));
  for (size_t i = 0; i < nparams; ++i) {
    const double v = s.drawn[kDrawnParameters + i];
    if (!(v >= ranges.parameters[i].lo && v <= ranges.parameters[i].hi))
      bad("drawn value of " + ranges.parameters[i].path + " outside its range");
  }
  if (s.previous_action.size() != action_.size()) bad("previous action of the wrong size");
  if (s.observation.size() != last_obs_.size()) bad("observation of the wrong size");
  for (Eigen::Index i = 0; i < s.state.y.size(); ++i)
    if (!std::isfinite(s.state.y[i])) bad("non-finite state value y[" + std::to_string(i) + "]");
  // the model of the drawn parameters (the shared one without any)
  const std::vector<double> keep = drawn_;
  std::shared_ptr<const Model> model = ctx_->scene.built.model;
  if (nparams > 0) {
    drawn_ = s.drawn;
    try {
      State unused = initialState(&model);
    } catch (...) {
      drawn_ = keep;
      throw;
    }
    drawn_ = keep;
  }
  const Model& m = *model;
  if (s.state.y.size() != m.stateSize())
    bad("state of " + std::to_string(s.state.y.size()) + " values, this scenario's has " + std::to_string(m.stateSize()));
  if (s.state.controls.size() != m.wheels.size() || s.state.applied.size() != m.wheels.size())
    bad("wheel controls for " + std::to_string(s.state.controls.size()) + " wheels, this scenario has " +
        std::to_string(m.wheels.size()));
  if (s.state.car_controls.size() != m.road_cars.size() || s.state.cars.size() != m.road_cars.size())
    bad("controls for " + std::to_string(s.state.car_controls.size()) + " road cars, this scenario has " +
        std::to_string(m.road_cars.size()));
  if (s.episode < 0 || s.episode_steps < 0) bad("negative episode counters");
  if (model != sim_->modelPtr()) {
    sim_ = std::make_unique<Simulator>(model, s.state);
    probe_ = std::make_unique<GroundProbe>(*sim_->model().ground);
    sensors_ = resolveSensors(*ctx_, sim_->model());
  } else {
    sim_->restore(s.state);
  }
  ranges_ = std::move(ranges);
  rng_.setState(s.rng);
  episode_ = s.episode;
  steps_ = s.episode_steps;
  return_ = s.episode_return;
  diverged_ = s.diverged;
  needs_reset_ = s.needs_reset;
  previous_ = s.previous_action;
  drawn_ = s.drawn;
  last_obs_ = s.observation;
  std::copy(last_obs_.begin(), last_obs_.end(), obs);
}

}  // namespace groundsim::experiments
