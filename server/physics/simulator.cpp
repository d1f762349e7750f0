#include "physics/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "physics/forces/body_contact.hpp"
#include "physics/forces/road_car_phase.hpp"
#include "physics/integrators/contact_phase.hpp"

namespace groundsim {

Simulator::Simulator(std::shared_ptr<const Model> model, State initial)
    : model_(std::move(model)), state_(std::move(initial)), ws_(*model_),
      integrator_(makeIntegrator(model_->opt.integrator)) {
  buildPath();
  restore(state_);
}

StepPath choosePath(const Model& m) {
  if (fastCarUnsupported(m) == nullptr) return StepPath::FastCar;
  if (ringCarUnsupported(m) == nullptr) return StepPath::RingCar;
  return StepPath::General;
}

const char* stepPathName(StepPath p) {
  switch (p) {
    case StepPath::General: return "general";
    case StepPath::FastCar: return "fast_car";
    case StepPath::RingCar: return "ring_car";
  }
  return "?";
}

void Simulator::buildPath() {
  path_ = choosePath(*model_);
  fast_.reset();
  ring_.reset();
  if (path_ == StepPath::FastCar) fast_ = std::make_unique<FastCar>(*model_);
  if (path_ == StepPath::RingCar) ring_ = std::make_unique<RingCar>(*model_);
}

namespace {

// What a step changes (y, time, the adaptive step, drive work, applied
// controls, the road cars' gears), copied into buffers of the same sizes:
// no allocation, and none of what a step leaves alone (commands, the
// initial energy, the health reason) is copied twice per step.
void saveForRollback(const State& s, State& to) {
  to.y = s.y;
  to.t = s.t;
  to.tick = s.tick;
  to.h_next = s.h_next;
  to.drive_work = s.drive_work;
  to.applied = s.applied;
  to.cars = s.cars;
}
void restoreFromRollback(const State& from, State& s) {
  s.y = from.y;
  s.t = from.t;
  s.tick = from.tick;
  s.h_next = from.h_next;
  s.drive_work = from.drive_work;
  s.applied = from.applied;
  s.cars = from.cars;
}

}  // namespace

bool Simulator::step() {
  if (state_.health != Health::Ok) return false;
  const Model& m = *model_;
  saveForRollback(state_, ws_.last_good);
  // (the adaptive integrator applies them over each of its substeps)
  if (!integrator_->appliesControls()) applyControls(m, m.opt.dt, state_);
  ws_.car_inputs = state_.cars;  // same size every step: no allocation
  bool plainly_healthy = false;
  // the specialised paths know no contact between bodies: while any pair
  // of collision groups may touch, the step takes the general loop
  const bool touching = m.collisions && groupsMayTouch(m, state_.y, m.opt.dt, ws_);
  ws_.step_pairs = m.collisions;
  // stiff contacts between bodies (and light objects on the ground) take
  // substeps that resolve them; the rest of the time the step is as set
  int n = std::max({1, m.opt.substeps, m.object_substeps});
  if (touching) n = std::max({n, contactSubsteps(m, state_.y, ws_, m.opt.dt), m.opt.collision.min_substeps});
  const double h = m.opt.dt / n;
  switch (touching ? StepPath::General : path_) {
    case StepPath::FastCar:
      plainly_healthy = fast_->step(m, state_, ws_);
      ws_stale_ = true;
      integrator_->evaluations += n;
      break;
    case StepPath::RingCar:
      ring_->step(m, state_, ws_);
      ws_stale_ = true;
      integrator_->evaluations += n;
      break;
    case StepPath::General:
      if (touching && n > 1 && contactPhaseApplies(m, ws_)) {
        // the contact's substeps without the rest of the forces (contact_phase.hpp)
        contactPhaseStep(m, state_, ws_, m.opt.dt, n);
        integrator_->evaluations += 1;
        contact_substeps_ += n;
      } else {
        for (int k = 0; k < n; ++k) integrator_->advance(m, state_, ws_, h);
        if (touching) contact_substeps_ += n;
      }
      ws_stale_ = false;
      break;
  }
  ws_.step_pairs = false;
  ws_.step_census = false;
  ++state_.tick;
  state_.t = static_cast<double>(state_.tick) * m.opt.dt;  // no drift from summing dt
  if (m.collisions) {
    if (touching) hits_.update(m, state_, ws_, m.opt.dt);
    else if (!hits_.active().empty()) {  // apart: end them
      ws_.pair_contacts.clear();
      hits_.update(m, state_, ws_, m.opt.dt);
    }
  }
  const bool energy = state_.tick % kEnergyCheckInterval == 0;
  if (plainly_healthy && !energy) return true;  // checkHealth would pass: skip its branches
  if (checkHealth(m, state_, ws_, energy)) return true;
  // divergence is terminal; keep the last finite state so nothing downstream
  // ever sees NaN, and report the reason through state().health
  const Health why = state_.health;
  std::string reason = std::move(state_.health_reason);
  restoreFromRollback(ws_.last_good, state_);
  state_.health = why;
  state_.health_reason = std::move(reason);
  return false;
}

void Simulator::restore(const State& s) {
  if (s.y.size() != model_->stateSize()) throw std::invalid_argument("state size does not match the model");
  if (&s != &state_) state_ = s;
  hits_.clear();
  state_.controls.resize(model_->wheels.size());
  state_.applied.resize(model_->wheels.size());
  state_.car_controls.resize(model_->road_cars.size());
  state_.cars.resize(model_->road_cars.size());
  ws_.car_inputs = state_.cars;
  if (state_.tick == 0) state_.initial_energy = energy().total();
}

void Simulator::refine(int substeps) {
  if (substeps < 1 || substeps > kMaxSubsteps)
    throw std::invalid_argument("substeps: 1 to " + std::to_string(kMaxSubsteps) + ", got " + std::to_string(substeps));
  if (substeps == model_->opt.substeps) return;
  (void)workspace();  // a specialised step's figures, exported before its kernel goes
  auto refined = std::make_shared<Model>(*model_);
  refined->opt.substeps = substeps;
  model_ = std::move(refined);
  const long long evaluations = integrator_->evaluations;
  integrator_ = makeIntegrator(model_->opt.integrator);
  integrator_->evaluations = evaluations;
  // the specialised kernels are built for a model: built again for this one
  buildPath();
}

bool Simulator::step(long long n) {
  for (long long i = 0; i < n; ++i)
    if (!step()) return false;
  return true;
}

int Simulator::roadCarIndex(int vehicle) const {
  for (size_t c = 0; c < model_->road_cars.size(); ++c)
    if (model_->road_cars[c].vehicle == vehicle) return static_cast<int>(c);
  return -1;
}

Energy Simulator::energy() const { return computeEnergy(*model_, state_, *ws_.diagnostics); }

}  // namespace groundsim
