// The experiments API's one interface: N independent environments of one
// scenario with a `task` section, stepped together. Implemented in process
// (experiments/vec_env.hpp, a thread pool over shared immutable models) and
// over LCM (client/experiments/remote_vec_env.hpp, a vectorised server
// session). The Python package wraps this interface, so both behave alike:
// the same seed and actions give bit-identical observations.
//
// Buffers are row-major, caller-owned and written in place (numpy arrays
// without copies), one row per agent of each environment (R = N x
// num_agents rows, environment-major): obs [R x obs_size] float32, actions
// [R x action_size] float32, rewards [R] float64, terminated/truncated [R]
// uint8. With one agent (the usual task) a row is an environment.
//
// Autoreset is Gymnasium's NEXT_STEP: an environment whose episode ended
// (terminated or truncated) in step k is reset by step k+1, whose action
// for it is ignored; that step returns the first observation of the new
// episode with reward 0 and both flags false.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace groundsim::experiments {

// Everything a client needs to interpret the buffers; also carried by the
// create reply and the session info of a vectorised server session.
struct Layout {
  int num_envs = 0;
  int num_agents = 1;               // agents per environment: each buffer has num_envs x num_agents rows
  std::vector<std::string> agents;  // their vehicles' names, the row order within an environment
  double dt = 0.0;                  // s      physics step
  int control_period = 1;           //        physics steps per action
  double time_limit = 0.0;          // s      truncation; 0 = none
  std::vector<std::string> observation;  // one name per component, e.g. "velocity_body.x"
  std::vector<float> observation_low, observation_high;  // -inf/+inf where unbounded
  std::vector<std::string> action;       // one name per component, e.g. "throttle"
  std::vector<float> action_low, action_high;
  std::vector<int> wheel_counts;    // per vehicle, in document order
  std::vector<std::string> drawn;   // what each reset draws: "x", "y", "yaw", "speed", then each parameter's path
  std::string scenario_hash;        // hex digest of the validated document (snapshots must match)
  int obsSize() const { return static_cast<int>(observation.size()); }
  int actionSize() const { return static_cast<int>(action.size()); }
  int drawnSize() const { return static_cast<int>(drawn.size()); }
  int rows() const { return num_envs * num_agents; }
};

// Bad calls from a client: wrong shapes, NaN actions, out-of-range seeds or
// env indices, a snapshot of another scenario or a corrupted one. `field`
// names what is wrong ("actions[3][1]", "snapshot", "seed", "env").
class ExperimentError : public std::runtime_error {
 public:
  ExperimentError(std::string field, const std::string& reason)
      : std::runtime_error(field + ": " + reason), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Per environment, after a step: what Gymnasium's infos carry.
struct EnvInfo {
  std::int64_t episode = 0;         // episodes started by this env (1 after the first reset)
  std::int64_t episode_steps = 0;   // actions taken in the current episode
  double episode_return = 0.0;      // sum of rewards in the current episode
  bool diverged = false;            // the physics diverged: the episode was terminated
  // the agent of this row took part in the last step (its reward and flags
  // are a transition); false once it finished, until the episode ends
  bool active = true;
};

class BatchEnv {
 public:
  virtual ~BatchEnv() = default;
  virtual const Layout& layout() const = 0;

  // Resets every environment. With a seed, environment i is seeded with
  // seed + i (seed in [0, 2^63)); without, each continues its own stream.
  virtual void reset(std::optional<std::uint64_t> seed, float* obs) = 0;
  // Resets one environment (options={"env": i} / reset to a chosen seed).
  // obs_rows: the environment's num_agents rows of obs
  virtual void resetEnv(int env, std::optional<std::uint64_t> seed, float* obs_rows) = 0;
  virtual void step(const float* actions, float* obs, double* rewards,
                    std::uint8_t* terminated, std::uint8_t* truncated) = 0;
  virtual EnvInfo info(int row) const = 0;

  // A full environment state (physics state, episode counters, random
  // stream, drawn parameters), restored bit for bit, also into another
  // process running the same scenario.
  virtual std::string snapshot(int env) const = 0;
  virtual void restore(int env, const std::string& snapshot, float* obs_rows) = 0;

  // A curriculum: new randomisation ranges for env (every env when env is
  // -1), drawn from at its next resets on. randomize_json: the task's
  // `randomize` object, every key optional; a parameter must be one the
  // task randomises, and both ends of its range must validate. Throws
  // ExperimentError naming the field ("randomize/x", ...); nothing changes then.
  virtual void setRandomization(int env, const std::string& randomize_json) = 0;
  // What each env's last reset drew, row-major [num_envs x Layout::drawnSize()]
  // (yaw in rad), for a privileged critic.
  virtual void drawn(double* out) const = 0;
  // A frame of env's scene (render/frame.hpp: a chase camera behind its
  // first agent's car, the page's ground and colours), height x width x 3
  // bytes, top row first. Throws ExperimentError("render_mode") where the
  // state is not at hand (a remote environment: render the same seed in
  // process, bit for bit the same run).
  virtual void render(int env, int width, int height, std::uint8_t* rgb) const = 0;
  virtual void close() {}
};

}  // namespace groundsim::experiments
