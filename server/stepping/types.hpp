// What the session layer exchanges with its transport (requests in,
// replies, state frames and events out) and what a re-simulation builds
// (frames): plain data, below the session layer so that the re-simulator
// and the CLI use it without the hosting code. The LCM adapter (server/lcm)
// translates these to and from the wire types; nothing here knows LCM.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "experiments/batch_env.hpp"
#include "physics/checks/telemetry.hpp"

namespace groundsim::stepping {

using Clock = std::chrono::steady_clock;
using TimePoint = Clock::time_point;

// Vectorised: N environments of a task, stepped only by VecOp::Step (session_info_t.MODE_VECTORISED).
enum class Mode : int { Realtime = 1, Fast = 2, Lockstep = 3, Vectorised = 4 };
enum class Status : int { Running = 1, Paused = 2, Finished = 3, Diverged = 4, Stopped = 5 };
enum class Op : int { Create = 1, List = 2, Stop = 3, Reset = 4, Pause = 5, Resume = 6, Step = 7, SetMode = 8,
                      Scenario = 9, Drain = 10 };
enum class Severity : int { Info = 0, Warning = 1, Error = 2 };

// Numbered as event_t.ERR_* so the adapter copies them unchanged.
enum class ErrorCode : int {
  None = 0, Decode = 1, Fingerprint = 2, UnknownSession = 3, BadScenario = 4,
  BadControl = 5, TooManySessions = 6, Unauthorized = 7, BadRequest = 8,
  WrongMode = 9, Diverged = 10, CommandTimeout = 11, Overrun = 12,
  Internal = 13, Shutdown = 14,
  // a create names assets (files) the server does not hold yet: the client
  // sends them (asset_part_t) and creates again (asset_want_t.ERR_MISSING_ASSETS)
  MissingAssets = 15,
  // a fleet could not take a create: its etcd did not answer while the
  // create was tried (FleetNode::kCreateRetry), or the server it named
  // cannot claim the session (lease lost, draining); nothing was created
  Unavailable = 16
};

const char* modeName(Mode m);
const char* statusName(Status s);
std::optional<Mode> modeFromInt(int m);

struct Request {
  Op op = Op::List;
  std::int64_t request_id = 0;
  std::string client_id;
  std::string session_id;
  std::string token;
  std::string scenario_json;      // Create
  double duration = 0.0;          // Create: s; 0 scenario's, < 0 unlimited
  int mode = 0;                   // Create/SetMode: Mode value, 0 = unchanged/default
  double rate = 0.0;              // real-time factor, 0 = unchanged/default
  double publish_rate = 0.0;      // Hz, 0 = unchanged/default
  std::int64_t steps = 0;         // Step
};

struct Drive {
  std::string client_id;
  std::string session_id;
  std::string token;
  int vehicle = 0;
  std::vector<WheelControl> wheels;  // the vehicle's wheels, in telemetry order
  TimePoint received{};
};

// Normalized controls of one road car (controls_t), checked by the service
// and applied with Simulator::setCarControls.
struct CarDrive {
  std::string client_id;
  std::string session_id;
  std::string token;
  int vehicle = 0;
  CarControls controls;              // throttle, brake, steer, handbrake, gear (wheel_torque unused)
  TimePoint received{};
};

// A road car's part of a frame: what the telemetry sample lacks.
struct CarFrame {
  int vehicle = 0;                   // index into Frame::vehicles
  CarControls commanded;
  CarRuntime applied;                // clamped controls, steer angle, engaged gear
};

// An object with mass at one instant (contact_state_t).
struct ObjectSample {
  int object = 0;                    // index among the model's objects
  Vec3 position = Vec3::Zero();      // m   shape centre
  Quat orientation = Quat::Identity();  // shape to world
  Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();
};

// One published state of a session: every vehicle at one instant. Values are
// finite by construction (Session::makeFrame sanitizes).
struct Frame {
  std::string session_id;
  std::int64_t seq = 0;
  double t = 0.0;
  std::int64_t tick = 0;
  Mode mode = Mode::Realtime;
  Status status = Status::Running;
  Health health = Health::Ok;
  std::string reason;
  double energy = 0.0;
  std::vector<VehicleSample> vehicles;
  std::vector<CarFrame> cars;        // the road cars among the vehicles (empty without)
  // scenes with contact between bodies: objects with mass and hits under
  // way (names from the model's collision groups)
  bool contacts = false;
  std::vector<ObjectSample> objects;
  std::vector<Hit> hits;
  std::shared_ptr<const Model> model;
  std::shared_ptr<const std::vector<std::string>> names;
  std::int64_t epoch = 0;            // the owner's claim (docs/fleet.md): 0 on a lone server
  double error_estimate = -1.0;      // the live error estimate (docs/accuracy.md); -1 without a tolerance
  // the last drive command applied before this frame: when the server got
  // it and when the session applied it (the latency trace, bench/web)
  TimePoint drive_received{}, drive_applied{};
};

struct SessionInfo {
  std::string session_id;
  std::string name;
  Mode mode = Mode::Realtime;
  Status status = Status::Running;
  std::string reason;
  double rate = 1.0;
  double publish_rate = 50.0;
  double t = 0.0;
  std::int64_t tick = 0;
  std::int64_t seq = -1;          // last published frame
  std::vector<std::string> vehicle_names;
  double idle_s = 0.0;
  double dt = 0.0;                // s  physics step
  std::vector<int> wheel_counts;  // per vehicle
  int control_period = 0;         // vectorised: physics steps per action, else 0
  int num_envs = 0;               // vectorised: environments, else 0
  std::shared_ptr<const experiments::Layout> layout;  // vectorised sessions
  std::string server_id;          // the owner (filled by the adapter when empty)
  std::int64_t epoch = 0;
};

struct Reply {
  Op op = Op::List;
  std::int64_t request_id = 0;
  std::string client_id;
  std::string session_id;
  bool ok = true;
  ErrorCode code = ErrorCode::None;
  std::string error;
  std::string token;
  std::string scenario_json;      // Create and Scenario: the session's scenario document
  std::string scenario_name;
  double t = 0.0;
  std::vector<SessionInfo> sessions;
  std::optional<Frame> state;
};

struct Event {
  std::string session_id;
  std::string client_id;
  std::int64_t request_id = 0;
  Severity severity = Severity::Error;
  ErrorCode code = ErrorCode::None;
  std::string channel;
  std::string reason;
  double t = 0.0;
  std::int64_t epoch = 0;         // the session's epoch when session_id is set
};

// A request to a vectorised session (vec_request_t), numbered as its OP_*.
enum class VecOp : int { Create = 1, Step = 2, Reset = 3, ResetEnv = 4, Snapshot = 5, Restore = 6, Randomize = 7,
                         Drawn = 8 };
const char* vecOpName(VecOp op);

struct VecRequest {
  VecOp op = VecOp::Step;
  std::int64_t request_id = 0;
  std::string client_id;
  std::string session_id;
  std::string token;
  std::string scenario_json;      // Create: a scenario with a `task`; Randomize: the `randomize` object
  int num_envs = 0;               // Create
  std::vector<float> actions;     // Step: [num_envs x action_size], row-major
  int env = 0;                    // ResetEnv, Snapshot, Restore, Randomize (-1: every env)
  bool has_seed = false;          // Reset, ResetEnv
  std::int64_t seed = 0;          // checked: [0, 2^63); env i of a Reset gets seed + i
  std::string snapshot;           // Restore
  TimePoint received{};
};

// The whole answer to a VecRequest; the transport splits it into parts.
// Arrays cover the environments [env_begin, env_begin + env_count).
struct VecReply {
  VecOp op = VecOp::Step;
  std::int64_t request_id = 0;
  std::string client_id;
  std::string session_id;
  bool ok = true;
  ErrorCode code = ErrorCode::None;
  std::string field;              // refusals: what is wrong
  std::string error;
  std::string token;              // Create
  std::int64_t tick = 0;          // batched steps taken
  std::vector<SessionInfo> sessions;  // Create: the session, with its layout
  int num_envs = 0;
  int env_begin = 0;
  int env_count = 0;
  int obs_size = 0;
  std::vector<float> obs;
  std::vector<double> rewards;
  std::vector<std::uint8_t> terminated, truncated;
  std::vector<experiments::EnvInfo> infos;
  std::string snapshot;           // Snapshot; Drawn: float64 LE [num_envs x drawnSize]
};

// Reply to a request, remembered until the request has been carried out.
struct ReplyTo {
  Op op = Op::List;
  std::int64_t request_id = 0;
  std::string client_id;
};

// What an owner sends its standbys so that a session survives its host
// (replica_t, docs/fleet.md). The transport adds the server id and seq.
struct Replica {
  enum class Kind : int { Scenario = 1, Snapshot = 2, Released = 3 };
  Kind kind = Kind::Snapshot;
  std::string session_id;
  std::int64_t epoch = 0;
  std::int64_t tick = 0;         // Snapshot: the session's tick
  std::int64_t applied_seq = 0;  // Snapshot: applied entries published before it
  std::int64_t frame_seq = 0;    // Snapshot: the seq of the next frame
  std::string meta;              // JSON: settings (Scenario), counters (Snapshot)
  std::string data;              // Scenario: the scenario document; Snapshot: the state's bytes
};

}  // namespace groundsim::stepping
