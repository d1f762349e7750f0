// The engine's front door: a model, its state, the workspace and the chosen
// integrator. The same class runs in the CLI (embedded) and in each server
// session.
#pragma once

#include <memory>

#include "physics/checks/contact_log.hpp"
#include "physics/checks/diagnostics.hpp"
#include "physics/forces/controls.hpp"
#include "physics/kernels/fast_car.hpp"
#include "physics/integrators/integrator.hpp"
#include "physics/core/model.hpp"
#include "physics/kernels/ring_car.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {


// The path a step takes while no pair of bodies may touch: the general
// loop (forces/, integrators/), or a specialised kernel the model allows.
enum class StepPath { General, FastCar, RingCar };
// The model's path: the rigid car's where fastCarUnsupported finds nothing
// in the way, else the ring car's where ringCarUnsupported does not, else
// the general loop. The substeps do not change it.
StepPath choosePath(const Model& m);
const char* stepPathName(StepPath p);

class Simulator {
 public:
  Simulator(std::shared_ptr<const Model> model, State initial);

  // One step of opt.dt (in opt.substeps integrator steps): integrate, then
  // check. On divergence returns false, sets state().health and its reason,
  // and restores the whole state from before the step (y, t, tick, h_next,
  // drive work, applied controls); later calls do nothing.
  bool step();
  bool step(long long n);

  // Steps from here on take `substeps` integrator steps per step of dt: a
  // refinement at a safe point (docs/accuracy.md, "Refinement"). The model
  // is copied with the new count; the state, its tick and the hits under
  // way stay, so the run goes on at the same times with a finer step. A
  // Simulator built on that model and given this state continues the same
  // way bit for bit (a re-simulation refines at the same tick).
  void refine(int substeps);

  const Model& model() const { return *model_; }
  std::shared_ptr<const Model> modelPtr() const { return model_; }
  const State& state() const { return state_; }
  // Restoring a saved state continues the run bit for bit.
  // A state at tick 0 (a scene's initial state) gets its initial energy,
  // the reference of the energy divergence check, computed here.
  void restore(const State& s);
  std::vector<WheelControl>& controls() { return state_.controls; }
  // A road car's controls (car: index among the model's road cars, see
  // roadCarIndex); they hold until set again.
  void setCarControls(int car, const CarControls& c) { state_.car_controls.at(static_cast<size_t>(car)) = c; }
  const CarControls& carControls(int car) const { return state_.car_controls.at(static_cast<size_t>(car)); }
  // The road car of a vehicle, or -1 when the vehicle is not one.
  int roadCarIndex(int vehicle) const;
  const Workspace& workspace() const {
    if (ws_stale_) {  // the specialised steps fill it on demand
      if (path_ == StepPath::FastCar) fast_->exportTo(*model_, ws_);
      else ring_->exportTo(*model_, ws_);
      ws_stale_ = false;
    }
    return ws_;
  }
  // Gauss-Seidel sweeps of the last step's friction solve, without filling
  // the workspace where the ring-car step has it already
  int frictionSweeps() const {
    return path_ == StepPath::FastCar ? workspace().friction_sweeps : ws_.friction_sweeps;
  }
  bool healthy() const { return state_.health == Health::Ok; }
  // The state, for advancing it outside this Simulator (BatchStep: many
  // environments' cars stepped together). The workspace then describes the
  // last step this Simulator took, not the state: a caller reads no
  // contact figures after batched steps (experiments' VecEnv batches only
  // tasks that observe none).
  State& batchState() { return state_; }
  long long forceEvaluations() const { return integrator_->evaluations; }
  // substeps of contact between bodies so far: in whole force evaluations,
  // or in the contact phase (contact_phase.hpp), where the rest of the
  // forces are evaluated once per step
  long long contactSubstepCount() const { return contact_substeps_; }
  // Which path steps take while no pair of bodies may touch (chosen once
  // per model: choosePath).
  StepPath stepPath() const { return path_; }
  // Whether steps take the specialised rigid-car path (fast_car.hpp).
  bool specialised() const { return path_ == StepPath::FastCar; }
  // Whether steps take the specialised ring-car path (ring_car.hpp).
  bool ringCar() const { return path_ == StepPath::RingCar; }
  // Energy of the current state, computed in the diagnostics' own scratch
  // (workspace().diagnostics): the last force evaluation stays as it was.
  Energy energy() const;

  // Hits between bodies under way after the last step, and those that
  // ended since the last takeEndedHits() (checks/contact_log.hpp).
  const std::vector<Hit>& hits() const { return hits_.active(); }
  std::vector<Hit> takeEndedHits() { return hits_.takeEnded(); }

  static constexpr int kEnergyCheckInterval = 256;
  static constexpr int kMaxSubsteps = 10000;  // as the scenario's physics.substeps

 private:
  std::shared_ptr<const Model> model_;
  State state_;
  mutable Workspace ws_;  // mutable: filled on demand after a specialised step
  mutable bool ws_stale_ = false;
  std::unique_ptr<Integrator> integrator_;
  long long contact_substeps_ = 0;
  // Builds the kernel of the path the model takes (buildPath) for model_.
  void buildPath();
  StepPath path_ = StepPath::General;
  // the kernel of path_: the rigid car's (fast_car.hpp) or the ring car's
  // (ring_car.hpp); none on the general path
  std::unique_ptr<FastCar> fast_;
  std::unique_ptr<RingCar> ring_;
  ContactLog hits_;
};

}  // namespace groundsim
