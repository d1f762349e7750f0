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

#include "drivers/track_course.hpp"
#include "experiments/batch_env.hpp"
#include "experiments/rng.hpp"
#include "experiments/sensors.hpp"
#include "experiments/snapshot.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::render {
struct FrameCache;
class Raster;
}

namespace groundsim::experiments {

// One agent: the vehicle it drives, found in the scene.
struct Agent {
  int vehicle = 0;                  // index among the scenario's vehicles
  int body = -1;                    // its chassis body
  int road_car = -1;                // its index among the road cars, -1 for the report's car
  std::array<int, 4> wheels{};      // report car: its wheels (model indices)
};

// Everything the environments of one scenario share, read-only once built.
struct TaskContext {
  scenario::Scenario scenario;      // validated, with its task
  scenario::Scene scene;            // the base scene: its model is shared
  nlohmann::json base_document;     // the validated document without `task`: drawn parameters apply to it
  scenario::Budget budget;
  scenario::FileAccess files;
  Layout layout;
  std::vector<Agent> agents;        // the task's agents (one unless it lists `agents`)
  double control_dt = 0.0;          // s   control_period * dt
  std::int64_t max_steps = 0;       // actions per episode before truncation; 0 = none
  // the scenario's race track, when the task reads it (TaskSpec::usesTrack)
  std::shared_ptr<const drivers::TrackCourse> track;

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

// Env::drawn(): what reset drew: per agent, in agent order, these four
// (kDrawnPerAgent values from kDrawnPerAgent * agent), then one value per
// task parameter (TaskSpec::randomize.parameters).
inline constexpr int kDrawnX = 0;          // m    start offset
inline constexpr int kDrawnY = 1;          // m
inline constexpr int kDrawnYaw = 2;        // rad
inline constexpr int kDrawnSpeed = 3;      // m/s
inline constexpr int kDrawnPerAgent = 4;
// then, when the task starts along its track (Randomization::along_track),
// one more: the distance along it (m) that every agent's start moved

// An agent's progress along the task's track this episode.
struct TrackProgress {
  drivers::TrackLine::Where at;  // where its body centre is on the line
  double travelled = 0.0;        // m gained along the line since the episode began
  int laps = 0;                  // laps completed and rewarded (a stage: 1 at its finish)
};
// Values of one agent's TrackProgress in a snapshot: s, offset, travelled, laps.
inline constexpr int kTrackValues = 4;

// One environment: its agents (one unless the task lists `agents`) act
// together; each has an observation row, an action row, a reward and flags.
// An agent that terminated stays out (its car brakes to rest, its rows read
// reward 0 and no flags, and it is not active) until the episode ends: when
// every agent has terminated, at the time limit, or when the physics
// diverges.
class Env {
 public:
  // Seeded with `seed` and reset; the first step() then starts episode 1
  // (as an autoreset: its action is ignored).
  Env(std::shared_ptr<const TaskContext> ctx, std::uint64_t seed);
  ~Env();

  // A new episode (seeded first when a seed is given); writes the first
  // observation of every agent (rows of obs).
  void reset(std::optional<std::uint64_t> seed, float* obs);
  // The actions to take, one row per agent, already checked finite; clipped
  // to the bounds here.
  void setAction(const float* actions);
  // Takes the actions set (or resets, when the last episode ended); one
  // value (or obs row) per agent.
  void step(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated);
  // step() in two halves around the physics, for VecEnv's batched path
  // (physics/kernels/batch_step.hpp, one agent only): beginStep resets an
  // ended episode (and returns false: nothing to step) or applies the
  // action; the caller then advances physicsState() by control_period
  // steps; finishStep evaluates the task.
  bool beginStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated);
  void finishStep(float* obs, double* reward, std::uint8_t* terminated, std::uint8_t* truncated);
  State& physicsState() { return sim_->batchState(); }
  EnvInfo info(int agent = 0) const;

  EnvSnapshot save() const;
  // Throws ExperimentError("snapshot", ...) when the payload does not fit
  // this task; the environment is unchanged then.
  void load(const EnvSnapshot& s, float* obs);

  const Simulator& simulator() const { return *sim_; }
  // A frame from behind the first agent's car (render/frame.hpp), of the
  // raster's size.
  void render(render::Raster& raster, std::uint8_t* rgb);
  // What the last reset drew (kDrawn* order, yaw in rad).
  const std::vector<double>& drawn() const { return drawn_; }
  // The ranges the next resets draw from: the task's, or a curriculum's
  // (validated by curriculumRanges, task_context.hpp).
  const scenario::Randomization& randomization() const { return ranges_; }
  void setRandomization(scenario::Randomization r) { ranges_ = std::move(r); }

 private:
  int agents() const { return static_cast<int>(ctx_->agents.size()); }
  void begin(float* obs);
  // Rebuilds the model for drawn parameters (or takes the shared one) and
  // returns the initial state for the drawn placements.
  State initialState(std::shared_ptr<const Model>* model) const;
  void useModel(std::shared_ptr<const Model> model, State s);
  void applyActions();
  void observe(float* obs);
  void addBumps();
  // Every agent located on the task's track (fresh: the whole line searched,
  // at a reset; else near where it was), its progress updated.
  void followTrack(bool fresh);
  // Agent a's reward terms from the track for the last action; sets *term
  // when its episode ends by them (off track beyond the limit, laps done).
  double trackReward(size_t a, bool* term);
  // Drawn offsets (and a distance along the track) applied to the start
  // pose of agent a.
  void placeAgent(int a, CarPlacement& at) const;

  std::shared_ptr<const TaskContext> ctx_;
  std::unique_ptr<Simulator> sim_;
  std::unique_ptr<GroundProbe> probe_;  // height samples, on the simulator's ground
  std::unique_ptr<render::FrameCache> frames_;  // render(): the ground patch, made on first use
  Rng rng_;
  std::vector<std::vector<Sensor>> sensors_;  // per agent, resolved on the simulator's model
  scenario::Randomization ranges_;  // what reset draws from
  std::vector<double> drawn_;       // kDrawn* order
  std::vector<float> action_, previous_;  // [agents x action_size]
  std::vector<float> last_obs_;     // [agents x obs_size]
  std::vector<double> feature_;     // one observation in double, before rounding to float
  std::int64_t episode_ = 0, steps_ = 0;
  std::vector<double> return_;      // per agent
  std::vector<double> bump_;        // per agent, m/s: velocity change given to its vehicle by hits this action
  std::vector<std::uint8_t> done_;  // per agent: terminated this episode
  std::vector<std::uint8_t> active_;  // per agent: took part in the last step (or episode just began)
  std::vector<Vec3> before_;        // per agent: chassis position when the current action was applied
  std::vector<TrackProgress> track_;  // per agent, when the task reads its track
  std::vector<double> gained_;      // per agent: m gained along the track by the last action
  bool diverged_ = false, needs_reset_ = false;
};

}  // namespace groundsim::experiments
