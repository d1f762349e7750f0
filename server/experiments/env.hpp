// One environment of a task: a Simulator, the task's evaluation
// (observation, reward, termination), its own random stream, episode
// counters and the previous action. Environments of one VecEnv share a
// TaskContext (immutable) and, unless the task randomises scenario
// parameters, its Model.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "experiments/batch_env.hpp"
#include "experiments/rng.hpp"
#include "experiments/sensors.hpp"
#include "experiments/snapshot.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::experiments {

// Everything the environments of one scenario share, read-only once built.
struct TaskContext {
  scenario::Scenario scenario;      // validated, with its task
  scenario::Scene scene;            // the base scene: its model is shared
  nlohmann::json base_document;     // the validated document without `task`: drawn parameters apply to it
  scenario::Budget budget;
  scenario::FileAccess files;
  Layout layout;
  int vehicle = 0;                  // the task's vehicle
  int body = -1;                    // its chassis body
  int road_car = -1;                // its index among the road cars, -1 for the report's car
  std::array<int, 4> wheels{};      // report car: its wheels (model indices)
  double control_dt = 0.0;          // s   control_period * dt
  std::int64_t max_steps = 0;       // actions per episode before truncation; 0 = none

  const scenario::TaskSpec& task() const { return *scenario.task; }
};

// Builds the context of a validated scenario with a task (throws
// ScenarioError for building problems, ExperimentError for a parameter range
// whose ends do not validate).
std::shared_ptr<const TaskContext> makeTaskContext(scenario::Scenario s, const scenario::Budget& budget,
                                                    const scenario::FileAccess& files);

// Whether VecEnv steps this task's cars together (physics/kernels/batch_step.hpp):
// when every environment keeps the shared model (no drawn parameters),
// BatchStep takes that model (the fast presets' rigid car on a plane), and
// no observed feature reads the workspace (wheel_contact, wheel_slip:
// batched steps do not fill it). Decided by the task alone.
bool stepsBatched(const TaskContext& c);

// Env::drawn(): what reset drew, in this order, then one value per task
// parameter (TaskSpec::parameters).
inline constexpr int kDrawnX = 0;          // m    start offset
inline constexpr int kDrawnY = 1;          // m
inline constexpr int kDrawnYaw = 2;        // rad
inline constexpr int kDrawnSpeed = 3;      // m/s
inline constexpr int kDrawnParameters = 4;

class Env {
 public:
  // Seeded with `seed` and reset; the first step() then starts episode 1
  // (as an autoreset: its action is ignored).
  Env(std::shared_ptr<const TaskContext> ctx, std::uint64_t seed);

  // A new episode (seeded first when a seed is given); writes the first
  // observation.
  void reset(std::optional<std::uint64_t> seed, float* obs);
  // The action to take, already checked finite; clipped to the bounds here.
  void setAction(const float* action);
  // Takes the action set (or resets, when the last episode ended).
  void step(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated);
  // step() in two halves around the physics, for VecEnv's batched path
  // (physics/kernels/batch_step.hpp): beginStep resets an ended episode (and returns
  // false: nothing to step) or applies the action; the caller then advances
  // physicsState() by control_period steps; finishStep evaluates the task.
  bool beginStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated);
  void finishStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated);
  State& physicsState() { return sim_->batchState(); }
  EnvInfo info() const;

  EnvSnapshot save() const;
  // Throws ExperimentError("snapshot", ...) when the payload does not fit
  // this task; the environment is unchanged then.
  void load(const EnvSnapshot& s, float* obs);

  const Simulator& simulator() const { return *sim_; }
  // What the last reset drew (kDrawn* order, yaw in rad).
  const std::vector<double>& drawn() const { return drawn_; }
  // The ranges the next resets draw from: the task's, or a curriculum's
  // (validated by curriculumRanges, task_context.hpp).
  const scenario::Randomization& randomization() const { return ranges_; }
  void setRandomization(scenario::Randomization r) { ranges_ = std::move(r); }

 private:
  void begin(float* obs);
  // Rebuilds the model for drawn parameters (or takes the shared one) and
  // returns the initial state for the drawn placement.
  State initialState(std::shared_ptr<const Model>* model) const;
  void applyAction();
  void observe(float* obs);

  std::shared_ptr<const TaskContext> ctx_;
  std::unique_ptr<Simulator> sim_;
  std::unique_ptr<GroundProbe> probe_;  // height samples, on the simulator's ground
  Rng rng_;
  std::vector<Sensor> sensors_;     // the observation, resolved on the simulator's model
  scenario::Randomization ranges_;  // what reset draws from
  std::vector<double> drawn_;       // kDrawn* order
  std::vector<float> action_, previous_;
  std::vector<float> last_obs_;
  std::vector<double> feature_;     // one observation in double, before rounding to float
  std::int64_t episode_ = 0, steps_ = 0;
  double return_ = 0.0;
  double bump_ = 0.0;  // m/s: velocity change given to the task's vehicle by hits this action
  void addBump();
  bool diverged_ = false, needs_reset_ = false;
  Vec3 before_ = Vec3::Zero();      // chassis position when the current action was applied
};

}  // namespace groundsim::experiments
