// One environment: reset (draws, initial state), step (action, physics,
// reward, flags), observation, save and load. Definitions of every feature
// and reward term: docs/scenario.md, "Tasks".
#include "experiments/env.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "experiments/task_context.hpp"
#include "render/frame.hpp"
#include "physics/kernels/batch_step.hpp"

namespace groundsim::experiments {
namespace {

using scenario::ActionKind;
using scenario::Feature;
using scenario::TaskSpec;

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

Env::Env(std::shared_ptr<const TaskContext> ctx, std::uint64_t seed) : ctx_(std::move(ctx)) {
  const Layout& l = ctx_->layout;
  const size_t n = static_cast<size_t>(agents());
  action_.assign(n * static_cast<size_t>(l.actionSize()), 0.0f);
  previous_ = action_;
  last_obs_.assign(n * static_cast<size_t>(l.obsSize()), 0.0f);
  feature_.assign(static_cast<size_t>(l.obsSize()), 0.0);
  return_.assign(n, 0.0);
  bump_.assign(n, 0.0);
  done_.assign(n, 0);
  active_.assign(n, 1);
  before_.assign(n, Vec3::Zero());
  track_.assign(n, TrackProgress{});
  gained_.assign(n, 0.0);
  ranges_ = ctx_->task().randomize;
  useModel(ctx_->scene.built.model, ctx_->scene.built.initial);
  reset(seed, last_obs_.data());
  // the first step() begins episode 1 (its action ignored), as after any end
  episode_ = 0;
  needs_reset_ = true;
}

void Env::useModel(std::shared_ptr<const Model> model, State s) {
  sim_ = std::make_unique<Simulator>(std::move(model), std::move(s));
  probe_ = std::make_unique<GroundProbe>(*sim_->model().ground);
  frames_.reset();  // a drawn parameter may change the ground the frames sampled
  sensors_.clear();
  for (int a = 0; a < agents(); ++a) sensors_.push_back(resolveSensors(*ctx_, a, sim_->model()));
}

void Env::placeAgent(int a, CarPlacement& at) const {
  const double* d = drawn_.data() + kDrawnPerAgent * a;
  if (ranges_.along_track) {
    // along the track and to its left, keeping the start's place on the grid
    const drivers::Pose2 moved =
        ctx_->track->moveAlong({{at.position.x(), at.position.y()}, at.yaw}, drawn_.back() + d[kDrawnX], d[kDrawnY]);
    at.position.x() = moved.p[0];
    at.position.y() = moved.p[1];
    at.yaw = moved.yaw + d[kDrawnYaw];
  } else {
    at.position.x() += d[kDrawnX];
    at.position.y() += d[kDrawnY];
    at.yaw += d[kDrawnYaw];
  }
  at.speed += d[kDrawnSpeed];
}

State Env::initialState(std::shared_ptr<const Model>* model) const {
  const std::vector<scenario::ParameterRange>& parameters = ranges_.parameters;
  const size_t offsets = static_cast<size_t>(kDrawnPerAgent * agents());
  const bool moved = ranges_.along_track || std::any_of(drawn_.begin(), drawn_.begin() + static_cast<std::ptrdiff_t>(offsets),
                                                        [](double d) { return d != 0.0; });
  if (parameters.empty() && !moved) {
    *model = ctx_->scene.built.model;
    return ctx_->scene.built.initial;
  }
  scenario::Scenario s;
  if (!parameters.empty()) {
    nlohmann::json doc = ctx_->base_document;
    for (size_t i = 0; i < parameters.size(); ++i)
      scenario::applyOverride(doc, overrideText(parameters[i].path, drawn_[offsets + i]), ctx_->budget);
    s = scenario::parseScenario(std::move(doc), ctx_->budget, ctx_->files);
  } else {
    s.options = ctx_->scenario.options;
    s.ground = ctx_->scenario.ground;
    s.vehicles = ctx_->scenario.vehicles;
    s.objects = ctx_->scenario.objects;
    s.document = nlohmann::json::object();
  }
  for (int a = 0; a < agents(); ++a)
    placeAgent(a, s.vehicles.at(static_cast<size_t>(ctx_->agents[static_cast<size_t>(a)].vehicle)).placement);
  scenario::Scene scene = scenario::buildScene(s);
  // only a drawn parameter changes the model: placements share the base one
  *model = parameters.empty() ? ctx_->scene.built.model : scene.built.model;
  return std::move(scene.built.initial);
}

void Env::reset(std::optional<std::uint64_t> seed, float* obs) {
  // a seeded reset starts a reproducible run: its episodes count from 1
  // again, so the same seed gives the same infos (Gymnasium's env checker)
  if (seed) {
    rng_.seed(*seed);
    episode_ = 0;
  }
  const scenario::Randomization& r = ranges_;
  const size_t offsets = static_cast<size_t>(kDrawnPerAgent * agents());
  drawn_.resize(offsets + r.parameters.size() + (r.along_track ? 1 : 0));
  // always four draws per agent for its placement, then one per parameter:
  // a task's stream does not depend on which ranges are empty
  for (size_t a = 0; a < offsets; a += kDrawnPerAgent) {
    drawn_[a + kDrawnX] = rng_.uniform(r.x[0], r.x[1]);
    drawn_[a + kDrawnY] = rng_.uniform(r.y[0], r.y[1]);
    drawn_[a + kDrawnYaw] = rng_.uniform(r.yaw_deg[0], r.yaw_deg[1]) * kDeg;
    drawn_[a + kDrawnSpeed] = rng_.uniform(r.speed[0], r.speed[1]);
  }
  for (size_t i = 0; i < r.parameters.size(); ++i)
    drawn_[offsets + i] = rng_.uniform(r.parameters[i].lo, r.parameters[i].hi);
  if (r.along_track) drawn_.back() = rng_.uniform(r.track_s[0], r.track_s[1]);
  std::shared_ptr<const Model> model;
  State s = initialState(&model);
  // the agents drive their vehicles from rest: no scripted drive of the scene
  for (const Agent& agent : ctx_->agents) {
    if (agent.road_car >= 0) {
      s.car_controls.at(static_cast<size_t>(agent.road_car)) = CarControls{};
    } else {
      for (int w : agent.wheels)
        if (w >= 0) s.controls.at(static_cast<size_t>(w)).drive_torque = 0.0;
    }
  }
  if (model != sim_->modelPtr()) useModel(std::move(model), std::move(s));
  else sim_->restore(s);
  begin(obs);
}

void Env::begin(float* obs) {
  ++episode_;
  steps_ = 0;
  std::fill(return_.begin(), return_.end(), 0.0);
  std::fill(done_.begin(), done_.end(), 0);
  std::fill(active_.begin(), active_.end(), 1);
  diverged_ = false;
  needs_reset_ = false;
  std::fill(previous_.begin(), previous_.end(), 0.0f);
  std::fill(action_.begin(), action_.end(), 0.0f);
  if (ctx_->track) {
    std::fill(track_.begin(), track_.end(), TrackProgress{});
    followTrack(true);
  }
  observe(obs);
}

void Env::followTrack(bool fresh) {
  const drivers::TrackLine& line = ctx_->track->line();
  const Eigen::VectorXd& y = sim_->state().y;
  // a car covers at most ~100 m/s x the control period between two calls
  const double reach = 50.0 + 100.0 * ctx_->control_dt;
  for (size_t a = 0; a < track_.size(); ++a) {
    gained_[a] = 0.0;
    if (!fresh && !active_[a]) continue;
    const Vec3 c = bodyPos(y, ctx_->agents[a].body);
    TrackProgress& p = track_[a];
    const double before = p.at.s;
    p.at = fresh ? line.locate({c.x(), c.y()}) : line.locate({c.x(), c.y()}, before, reach);
    if (!fresh) gained_[a] = ctx_->track->gained(before, p.at.s);
    p.travelled += gained_[a];
  }
}

double Env::trackReward(size_t a, bool* term) {
  const TaskSpec& t = ctx_->task();
  const drivers::TrackCourse& course = *ctx_->track;
  TrackProgress& p = track_[a];
  const Vec3 c = bodyPos(sim_->state().y, ctx_->agents[a].body);
  const double beyond = course.beyondEdge({c.x(), c.y()}, p.at);
  // a circuit's lap is its length travelled (from wherever the start was); a
  // stage is done within a metre of its finish
  constexpr double kFinishSlack = 1.0;  // m
  const int laps = course.circuit() ? static_cast<int>(std::floor(p.travelled / course.finish()))
                                    : (p.at.s >= course.finish() - kFinishSlack ? 1 : 0);
  double r = t.reward.track_progress * gained_[a];
  if (laps > p.laps) {
    r += t.reward.lap * (laps - p.laps);
    p.laps = laps;
  }
  if (beyond > 0.0) r -= t.reward.off_track;
  if (t.off_track_end > 0.0 && beyond > t.off_track_end) *term = true;
  if (t.laps > 0 && p.laps >= t.laps) *term = true;
  return r;
}

void Env::setAction(const float* a) {
  const Layout& l = ctx_->layout;
  const size_t k = static_cast<size_t>(l.actionSize());
  for (size_t i = 0; i < action_.size(); ++i) action_[i] = std::clamp(a[i], l.action_low[i % k], l.action_high[i % k]);
}

void Env::applyActions() {
  const TaskSpec& t = ctx_->task();
  const size_t k = static_cast<size_t>(ctx_->layout.actionSize());
  for (size_t a = 0; a < ctx_->agents.size(); ++a) {
    const Agent& agent = ctx_->agents[a];
    const int rc = agent.road_car;
    const float* act = action_.data() + a * k;
    const bool out = done_[a] != 0;  // a finished agent's car brakes to rest
    if (t.action == ActionKind::CarControls) {
      CarControls c = sim_->carControls(rc);
      c.throttle = out ? 0.0f : act[0];
      c.brake = out ? 1.0f : act[1];
      c.steer = out ? 0.0f : act[2];
      c.handbrake = !out && t.handbrake && act[3] > 0.5f;
      sim_->setCarControls(rc, c);
    } else if (rc >= 0) {
      CarControls c = sim_->carControls(rc);
      for (size_t w = 0; w < 4; ++w) c.wheel_torque[w] = out ? 0.0f : act[w];
      c.brake = out ? 1.0f : c.brake;
      sim_->setCarControls(rc, c);
    } else {
      for (size_t w = 0; w < 4; ++w)
        if (agent.wheels[w] >= 0) sim_->controls()[static_cast<size_t>(agent.wheels[w])].drive_torque = out ? 0.0 : act[w];
    }
  }
}

bool stepsBatched(const TaskContext& c) {
  const scenario::TaskSpec& t = c.task();
  if (c.agents.size() != 1 || !t.randomize.parameters.empty() || BatchStep::unsupported(*c.scene.built.model) != nullptr)
    return false;
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
    if (bumps) addBumps();
  }
  finishStep(obs, reward, terminated, truncated);
}

// The hits of each agent's vehicle this step, as the velocity change they
// give it: |force| dt / its mass (a reward term that means the same for a
// 1.4 kg car and a 1.5 t one).
void Env::addBumps() {
  const Model& m = sim_->model();
  for (const Hit& h : sim_->hits()) {
    const CollisionGroup& a = m.groups[h.a];
    const CollisionGroup& b = m.groups[h.b];
    for (size_t k = 0; k < ctx_->agents.size(); ++k) {
      const int vehicle = ctx_->agents[k].vehicle;
      const CollisionGroup* mine = a.vehicle == vehicle ? &a : b.vehicle == vehicle ? &b : nullptr;
      if (mine && mine->mass > 0.0) bump_[k] += h.force.norm() * m.opt.dt / mine->mass;
    }
  }
}

bool Env::beginStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated) {
  const size_t n = ctx_->agents.size();
  if (needs_reset_) {
    reset(std::nullopt, obs);
    std::fill(reward, reward + n, 0.0);
    std::fill(terminated, terminated + n, std::uint8_t{0});
    std::fill(truncated, truncated + n, std::uint8_t{0});
    return false;
  }
  for (size_t a = 0; a < n; ++a) {
    before_[a] = bodyPos(sim_->state().y, ctx_->agents[a].body);
    active_[a] = done_[a] ? 0 : 1;
  }
  std::fill(bump_.begin(), bump_.end(), 0.0);
  applyActions();
  return true;
}

void Env::finishStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated) {
  const TaskSpec& t = ctx_->task();
  const Layout& l = ctx_->layout;
  const size_t n = ctx_->agents.size(), k = static_cast<size_t>(l.actionSize());
  diverged_ = !sim_->healthy();
  ++steps_;
  const bool time_up = ctx_->max_steps > 0 && steps_ >= ctx_->max_steps;
  const Eigen::VectorXd& y = sim_->state().y;
  if (ctx_->track) followTrack(false);
  bool all_done = true;
  for (size_t a = 0; a < n; ++a) {
    if (!active_[a]) {  // finished earlier: nothing to report
      reward[a] = 0.0;
      terminated[a] = truncated[a] = 0;
      continue;
    }
    const int b = ctx_->agents[a].body;
    const Vec3 before = before_[a];
    const double gx = t.goal[0], gy = t.goal[1];
    const double dist_before = std::hypot(gx - before.x(), gy - before.y());
    const Vec3 c = bodyPos(y, b);
    const Mat3 R = bodyRotation(y, b);
    const double dist = std::hypot(gx - c.x(), gy - c.y());
    const double up_z = std::clamp(R(2, 2), -1.0, 1.0);
    const bool at_goal = t.goal_radius > 0.0 && dist <= t.goal_radius;

    // reward terms (docs/scenario.md): each finite by construction, the
    // actions normalised to [-1, 1] by their bounds' largest magnitude
    const float* act = action_.data() + a * k;
    const float* prev = previous_.data() + a * k;
    double effort = 0.0, jerk = 0.0;
    for (size_t j = 0; j < k; ++j) {
      const double scale = std::max(std::abs(l.action_low[j]), std::abs(l.action_high[j]));
      const double u = act[j] / scale, p = prev[j] / scale;
      effort += u * u;
      jerk += (u - p) * (u - p);
    }
    const double na = static_cast<double>(std::max<size_t>(k, 1));
    const double v_forward = (R.transpose() * Vec3(bodyVel(y, b))).x();
    const double dv = (v_forward - t.target_speed) / t.speed_tolerance;
    const scenario::RewardWeights& w = t.reward;
    double r = 0.0;
    if (w.progress_to_goal != 0.0) r += w.progress_to_goal * (dist_before - dist);
    if (w.progress_along != 0.0)
      r += w.progress_along * ((c.x() - before.x()) * t.direction[0] + (c.y() - before.y()) * t.direction[1]);
    if (w.speed_tracking != 0.0) r += w.speed_tracking * std::exp(-dv * dv);
    if (w.effort != 0.0) r -= w.effort * effort / na;
    if (w.jerk != 0.0) r -= w.jerk * jerk / na;
    if (w.tilt != 0.0) r -= w.tilt * (1.0 - up_z);
    if (w.collision != 0.0) r -= w.collision * bump_[a];
    r += w.alive;
    if (at_goal) r += w.goal;
    bool track_end = false;
    if (ctx_->track) r += trackReward(a, &track_end);
    if (!std::isfinite(r)) r = 0.0;

    bool term = diverged_ || at_goal || track_end;
    if (t.max_tilt_deg > 0.0 && std::acos(up_z) > t.max_tilt_deg * kDeg) term = true;
    if (t.has_region && (c.x() < t.region_min[0] || c.x() > t.region_max[0] || c.y() < t.region_min[1] ||
                         c.y() > t.region_max[1]))
      term = true;
    const bool trunc = !term && time_up;
    return_[a] += r;
    reward[a] = r;
    terminated[a] = term ? 1 : 0;
    truncated[a] = trunc ? 1 : 0;
    if (term) done_[a] = 1;
    all_done = all_done && (term || trunc);
  }
  previous_ = action_;  // same size: no allocation
  observe(obs);
  needs_reset_ = all_done || time_up || diverged_;
}

void Env::observe(float* obs) {
  const size_t o = feature_.size();
  SensorInputs in;
  in.probe = probe_.get();
  in.time = static_cast<double>(steps_) * ctx_->control_dt;
  in.fresh = steps_ == 0;  // nothing has touched the ground yet this episode
  for (size_t a = 0; a < ctx_->agents.size(); ++a) {
    // a finished agent's row keeps its last observation
    if (done_[a] && !active_[a]) continue;
    in.previous_action = previous_.data() + a * static_cast<size_t>(ctx_->layout.actionSize());
    in.track = ctx_->track ? &track_[a].at : nullptr;
    readSensors(sensors_[a], *ctx_, static_cast<int>(a), sim_->model(), sim_->state(), sim_->workspace(), in,
                feature_.data());
    for (size_t i = 0; i < o; ++i) last_obs_[a * o + i] = drivers::publishedFloat(feature_[i]);
  }
  if (obs != last_obs_.data()) std::copy(last_obs_.begin(), last_obs_.end(), obs);
}

Env::~Env() = default;

void Env::render(render::Raster& raster, std::uint8_t* rgb) {
  if (!frames_) frames_ = std::make_unique<render::FrameCache>();
  render::renderFrame(sim_->model(), sim_->state(), *probe_, ctx_->agents.front().body, render::FrameOptions{}, raster,
                      *frames_, rgb);
}

EnvInfo Env::info(int agent) const {
  EnvInfo i;
  i.episode = episode_;
  i.episode_steps = steps_;
  i.episode_return = return_[static_cast<size_t>(agent)];
  i.diverged = diverged_;
  i.active = active_[static_cast<size_t>(agent)] != 0;
  return i;
}

EnvSnapshot Env::save() const {
  EnvSnapshot s;
  s.state = sim_->state();
  s.rng = rng_.state();
  s.episode = episode_;
  s.episode_steps = steps_;
  s.returns = return_;
  s.done = done_;
  s.active = active_;
  s.diverged = diverged_;
  s.needs_reset = needs_reset_;
  s.previous_action = previous_;
  s.drawn = drawn_;
  s.ranges = rangesJson(ranges_).dump();
  s.observation = last_obs_;
  if (ctx_->track)
    for (const TrackProgress& p : track_)
      s.track.insert(s.track.end(), {p.at.s, p.at.offset, p.travelled, static_cast<double>(p.laps)});
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
  const size_t nparams = ranges.parameters.size(), offsets = static_cast<size_t>(kDrawnPerAgent * agents());
  const size_t ndrawn = offsets + nparams + (ranges.along_track ? 1 : 0);
  if (s.drawn.size() != ndrawn)
    bad(std::to_string(s.drawn.size()) + " drawn values, this task draws " + std::to_string(ndrawn));
  for (size_t i = 0; i < nparams; ++i) {
    const double v = s.drawn[offsets + i];
    if (!(v >= ranges.parameters[i].lo && v <= ranges.parameters[i].hi))
      bad("drawn value of " + ranges.parameters[i].path + " outside its range");
  }
  if (s.previous_action.size() != action_.size()) bad("previous action of the wrong size");
  if (s.observation.size() != last_obs_.size()) bad("observation of the wrong size");
  const size_t ntrack = ctx_->track ? kTrackValues * static_cast<size_t>(agents()) : 0;
  if (s.track.size() != ntrack)
    bad(std::to_string(s.track.size()) + " track progress values, this task keeps " + std::to_string(ntrack));
  for (double v : s.track)
    if (!std::isfinite(v)) bad("non-finite track progress");
  const size_t n = static_cast<size_t>(agents());
  if (s.returns.size() != n || s.done.size() != n || s.active.size() != n)
    bad("per-agent counters for " + std::to_string(s.returns.size()) + " agents, this task has " + std::to_string(n));
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
  if (model != sim_->modelPtr()) useModel(std::move(model), s.state);
  else sim_->restore(s.state);
  ranges_ = std::move(ranges);
  rng_.setState(s.rng);
  episode_ = s.episode;
  steps_ = s.episode_steps;
  return_ = s.returns;
  done_ = s.done;
  active_ = s.active;
  diverged_ = s.diverged;
  needs_reset_ = s.needs_reset;
  previous_ = s.previous_action;
  drawn_ = s.drawn;
  last_obs_ = s.observation;
  for (size_t a = 0; a < track_.size() && !s.track.empty(); ++a) {
    const double* v = s.track.data() + kTrackValues * a;
    track_[a].at = {v[0], v[1]};
    track_[a].travelled = v[2];
    track_[a].laps = static_cast<int>(std::clamp(v[3], -1e6, 1e6));
  }
  std::copy(last_obs_.begin(), last_obs_.end(), obs);
}

}  // namespace groundsim::experiments
