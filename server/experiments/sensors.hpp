// A task's observation, resolved once: each feature of the task becomes
// sensors that know their source (which body, state entry, wheel or
// workspace slot) and their output slot, as MuJoCo resolves its sensors
// when the model is built. Reading them is then one loop of one-line cases
// (readSensors); nothing decides road car versus wheel car at a step.
#pragma once

#include <vector>

#include "drivers/track_line.hpp"
#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {
class GroundProbe;
}

namespace groundsim::experiments {

struct TaskContext;

struct Sensor {
  enum class Kind {
    Zero,            // 1  a wheel the vehicle does not have
    Position,        // 3  body centre, world
    Heading,         // 2  cos, sin of the yaw
    UpBody,          // 3  world vertical in the body frame
    VelocityBody,    // 3
    AngularVelocityBody,  // 3
    Speed,           // 1
    StateEntry,      // 1  y[index]: a road car's wheel spin or strut travel
    WheelSpin,       // 1  model wheel `index`: spin relative to its carrier
    RoadContact,     // 1  road car `index`, wheel `wheel`: touching (0 before the first step)
    RoadSlip,        // 1  road car `index`, wheel `wheel`: slip ratio (0 before the first step)
    WheelContact,    // 1  model wheel `index` pressed on the ground (0 before the first step)
    WheelSlip,       // 1  model wheel `index`: largest contact slip speed (0 before the first step)
    HeightSample,    // 1  ground below (ahead, lateral) minus the body centre's height
    GoalBody,        // 2
    GoalDistance,    // 1
    PreviousAction,  // 1  component `index` of the previous action
    Time,            // 1
    OtherAgent,      // 4  agent `index` relative to this one: position x, y and velocity x, y in the body frame
    TrackAhead,      // 2t the task's track (drivers/track_course.hpp), from SensorInputs::track
    TrackPose,       // 3
    TrackCurvature,  // t
    NextGate,        // 2
  };
  Kind kind = Kind::Zero;
  int slot = 0;          // first output component
  int index = 0;         // state entry, wheel, road car or action component, by kind
  int wheel = 0;         // RoadContact, RoadSlip
  double ahead = 0.0, lateral = 0.0;  // HeightSample, m
};

// Body-to-world rotation of body b (its quaternion normalised).
Mat3 bodyRotation(const Eigen::VectorXd& y, int b);

// The sensors of agent `agent` of the context's task on model m (in the
// order and with the slots of the Layout).
std::vector<Sensor> resolveSensors(const TaskContext& ctx, int agent, const Model& m);

// What a sensor reads besides the physics.
struct SensorInputs {
  GroundProbe* probe = nullptr;  // the env's, on its simulator's ground
  const float* previous_action = nullptr;
  double time = 0.0;      // s since the episode began
  bool fresh = false;     // no step taken yet this episode: contact and slip read 0
  const drivers::TrackLine::Where* track = nullptr;  // the agent on the task's track (track features)
};

// Writes every sensor's components of agent `agent` into out (doubles;
// Layout order).
void readSensors(const std::vector<Sensor>& sensors, const TaskContext& ctx, int agent, const Model& m,
                 const State& s, const Workspace& ws, const SensorInputs& in, double* out);

}  // namespace groundsim::experiments
