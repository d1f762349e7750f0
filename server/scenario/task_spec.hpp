// The validated `task` section (task_section.cpp): what an agent sees,
// commands and is rewarded for, when its episode ends, and what is drawn at
// random at each reset. The experiments layer (server/experiments) turns it
// into observations, rewards and flags; docs/scenario.md defines each field.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace groundsim::scenario {

// Observation features, in the order the task lists them; each contributes
// a fixed number of components (experiments/task_layout.cpp names them).
enum class Feature {
  Position,             // 3  body centre, world (m)
  Heading,              // 2  cos, sin of the yaw (forward axis projected on the ground plane)
  UpBody,               // 3  world vertical in the body frame
  VelocityBody,         // 3  body-centre velocity in the body frame (m/s)
  AngularVelocityBody,  // 3  body angular velocity in the body frame (rad/s)
  Speed,                // 1  |velocity| (m/s)
  WheelSpin,            // n  wheel spin relative to the carrier (rad/s, + = forward)
  WheelContact,         // n  1 when the wheel touched the ground in the last step, else 0
  WheelSlip,            // n  road car: slip ratio; report car: largest contact slip speed (m/s)
  SuspensionTravel,     // 4  road car only: strut travel (m, + = compression)
  HeightSamples,        // a*l ground height minus body-centre height at a grid ahead of the car (m)
  GoalBody,             // 2  horizontal offset to the goal, in the body frame (m)
  GoalDistance,         // 1  horizontal distance to the goal (m)
  PreviousAction,       // k  the last action taken (after clipping), 0 after a reset
  Time,                 // 1  time since the episode started (s)
  AgentsBody,           // 4(A-1) each other agent's position (x, y) and velocity (x, y) relative to
                        //    this one, in its body frame (m, m/s); A = number of agents
  // the scenario's race track (drivers/track_course.hpp): the centre line
  // a driver follows, located from the car's body centre
  TrackAhead,           // 2t the line's point at each `track.ahead` distance past the car, body frame (m)
  TrackPose,            // 3  offset from the line (m, + = left), sin and cos of the heading error
  TrackCurvature,       // t  the line's curvature at each `track.ahead` distance (1/m, + = left)
  NextGate,             // 2  the centre of the next gate along the line, body frame (m)
};

// Feature names as written in a task, in enum order.
const std::vector<std::string>& featureNames();

enum class ActionKind {
  CarControls,   // road car: throttle [0,1], brake [0,1], steer [-1,1] (+ handbrake [0,1], on above 0.5)
  WheelTorques,  // drive torque per wheel in [-max_torque, max_torque] N m
};

// A scenario value drawn at each reset, applied like `--set path=value`.
struct ParameterRange {
  std::string path;                 // dotted, e.g. "ground.amplitude", "vehicle.mass"
  double lo = 0.0, hi = 0.0;
};

// What a reset draws, uniformly in [lo, hi]: the initial state's offsets,
// then each parameter. A curriculum may change the ranges while training
// (readCurriculum), never which parameters there are.
struct Randomization {
  std::array<double, 2> x{0.0, 0.0}, y{0.0, 0.0};  // m
  std::array<double, 2> yaw_deg{0.0, 0.0};           // deg
  std::array<double, 2> speed{0.0, 0.0};             // m/s
  std::vector<ParameterRange> parameters;
  // a task on a race track may start anywhere along it: the agents' start
  // poses are moved by a distance drawn from track_s along the line (x and
  // y are then offsets along it and to its left)
  bool along_track = false;
  std::array<double, 2> track_s{0.0, 0.0};           // m
};

struct RewardWeights {
  double progress_to_goal = 0.0;    // per metre the goal distance shrank during the action
  double progress_along = 0.0;      // per metre moved along `direction`
  double speed_tracking = 0.0;      // exp(-((v_forward - target_speed) / speed_tolerance)^2)
  double effort = 0.0;              // -mean(a_normalised^2)
  double jerk = 0.0;                // -mean((a_normalised - previous)^2)
  double tilt = 0.0;                // -(1 - cos(tilt))
  double alive = 0.0;               // +1 per action
  double goal = 0.0;                // +1 on the action that reaches the goal
  double collision = 0.0;           // -(velocity change from hits with other bodies and objects, m/s)
  double track_progress = 0.0;      // per metre gained along the race track's line
  double lap = 0.0;                 // +1 on the action that completes a lap (a stage: reaches its finish)
  double off_track = 0.0;           // -1 per action ending off the track (farther than its half width)
};

struct TaskSpec {
  int vehicle = 0;                  // index among the scenario's vehicles (agents[0])
  std::vector<int> agents{0};       // the vehicles an agent each drives: {vehicle}, or the task's `agents`
  std::vector<Feature> observation;
  std::vector<double> height_ahead{2.0, 4.0, 6.0};  // m  grid distances along the heading
  std::vector<double> height_lateral{0.0};          // m  offsets to the left (+) / right (-)
  ActionKind action = ActionKind::CarControls;
  bool handbrake = false;           // CarControls: a fourth component
  double max_torque = 1.0;          // N m  WheelTorques
  int control_period = 1;           // physics steps per action
  double time_limit = 0.0;          // s    truncation; 0 = none
  bool has_goal = false;
  std::array<double, 2> goal{0.0, 0.0};       // m  world x, y
  std::array<double, 2> direction{1.0, 0.0};  // unit, horizontal (progress_along)
  double target_speed = 0.0;        // m/s
  double speed_tolerance = 1.0;     // m/s
  RewardWeights reward;
  double max_tilt_deg = 0.0;        // terminate beyond this tilt; 0 = never
  bool has_region = false;          // terminate when the body centre leaves [min, max] (x, y)
  std::array<double, 2> region_min{0.0, 0.0}, region_max{0.0, 0.0};
  double goal_radius = 0.0;         // terminate within this distance of the goal; 0 = never
  double off_track_end = 0.0;       // m  terminate this far beyond the track's edge; 0 = never
  int laps = 0;                     // terminate after this many laps (a stage: at its finish); 0 = never
  std::vector<double> track_ahead{5.0, 10.0, 20.0, 40.0};  // m  distances of track_ahead, track_curvature
  Randomization randomize;

  // Whether any feature, reward or termination reads the race track.
  bool usesTrack() const;
};

// A curriculum's `randomize` object (the task's schema, every key
// optional): new ranges for the offsets given, and for parameters named by
// path, each one of `current`'s. Throws ScenarioError (pointers under
// /randomize) for anything else; the parameters' ends are checked against
// the scenario by the experiments layer.
Randomization readCurriculum(nlohmann::json randomize, const Randomization& current);

// Most parameters a task may randomise, most height samples, most agents.
inline constexpr int kMaxTaskParameters = 64;
inline constexpr int kMaxAgents = 16;
inline constexpr int kMaxHeightSamples = 1024;
inline constexpr int kMaxTrackAhead = 64;

}  // namespace groundsim::scenario
