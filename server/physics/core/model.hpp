// The immutable model: everything that does not change while a scene runs.
// Built once (ModelBuilder, vehicle builder) from a validated scenario; every
// engine function takes `const Model&` and a mutable `State` (state.hpp),
// as MuJoCo does with mjModel / mjData.
#pragma once

#include <string>
#include <vector>

#include "physics/collision/collision.hpp"
#include "physics/ground/ground.hpp"
#include "physics/base/math.hpp"
#include "physics/road_car/road_car.hpp"

namespace groundsim {

enum class IntegratorKind { SemiImplicitEuler, VelocityVerlet, Rk4, ImplicitEuler, Adaptive };
enum class FrictionModel {
  StickSlip,    // velocity-level Coulomb clamp: sticks exactly, no chatter, no creep
  Regularized,  // mu N tanh(|u|/v_s): smooth, creeps at v_s atanh(tan(theta)/mu)
  Sign          // the report's mu N u/|u|: chatters at zero slip (kept for comparison)
};
enum class NormalDamping { KelvinVoigt, HuntCrossley };
enum class WheelContact { RimPoints, Circle };

// Ground contact (report eq. 10 plus damping and friction choices).
struct ContactParams {
  double stiffness = 2000.0;       // N/m      S: penalty force per metre of depth
  double damping = 0.0;            // N s/m    Kelvin-Voigt c, or Hunt-Crossley alpha [s/m]
  NormalDamping damping_model = NormalDamping::KelvinVoigt;
  double friction = 0.5;           // -        Coulomb mu
  FrictionModel friction_model = FrictionModel::StickSlip;
  double slip_velocity = 0.01;     // m/s      regularisation scale v_s
  int friction_iterations = 50;    // -        most Gauss-Seidel sweeps over contacts and brakes (stops once converged)
};

// Bounds beyond which a run is declared diverged (checkHealth, diagnostics.hpp).
struct Limits {
  double max_penetration = 0.5;    // m
  double max_speed = 1000.0;       // m/s     any body or particle
  // energy may exceed (initial energy + drive work) by at most this fraction
  // of (|initial energy| + |drive work| + total weight * 1 m)
  double max_energy_growth = 1.0;  // -
};

struct Options {
  double dt = 5e-5;                // s       step of the fixed-step integrators; output step of adaptive
  IntegratorKind integrator = IntegratorKind::SemiImplicitEuler;
  double tolerance = 1e-6;         // -       adaptive: relative local error per step
  int substeps = 1;                // -       integrator steps per step()
  bool broad_phase = true;         // -       skip bodies provably clear of the ground (off: for tests)
  // the same bits on every x86-64 machine: the hot loops take their generic
  // (SSE2, no FMA) build even where the CPU has AVX2 (simd_path.hpp)
  bool deterministic = false;
  Vec3 gravity{0.0, 0.0, -9.8};    // m/s^2   the report's g = 9.8
  ContactParams contact;
  CollisionParams collision;       // contact between bodies (collision/collision.hpp)
  Limits limits;
};

// A rigid body made of mass points (report eqs. 3-9). Its frame sits at the
// centre of mass; point offsets are given in that frame.
struct Body {
  std::string name;
  double mass = 0.0;               // kg
  Mat3 inertia = Mat3::Zero();     // kg m^2  about the centre of mass, body frame
  Mat3 inv_inertia = Mat3::Zero();
  double bound_radius = 0.0;       // m       largest distance of a contact point from the COM
  bool has_contact_points = false;
  // an object's own ground contact law (collision_build.cpp), from its mass
  // like the contact between bodies; 0 / < 0: the scene's contact.stiffness
  // and contact.damping
  double ground_stiffness = 0.0;   // N/m    per contact point
  double ground_damping = -1.0;    // N s/m  per contact point
};

// A free point mass (the report's non-rigid bodies).
struct Particle {
  double mass = 0.0;               // kg
  bool contact = true;
};

// An attachment point: on a body (offset `local` in the body frame) or a
// particle. Springs and contacts refer to points.
struct Point {
  int body = -1;                   // body index, or -1
  int particle = -1;               // particle index, or -1
  Vec3 local = Vec3::Zero();       // m       offset in the body frame
  bool contact = false;            // takes part in ground contact
  int wheel = -1;                  // wheel whose rim this point belongs to (telemetry)
  int steer_wheel = -1;            // this point turns with that wheel's steering angle
  Vec3 steer_pivot = Vec3::Zero(); // m       pivot of that rotation, body frame
};

// Spring-dashpot between two points (report eq. 1, with the dashpot acting on
// the rate of change of length as eq. 1 says, not |U_j - U_k| as eq. 13 does).
struct Spring {
  int a = -1, b = -1;              // point indices
  double stiffness = 0.0;          // N/m
  double damping = 0.0;            // N s/m
  double rest_length = 0.0;        // m
  // zero-length isotropic spring k (x_b - x_a) + c (u_b - u_a): a ball joint
  // by penalty; two of them along an axis make a hinge
  bool isotropic = false;
};

// A wheel: a rigid body turning about `axis` relative to its carrier body,
// driven and braked by torques with the reaction on the carrier.
struct Wheel {
  int body = -1;                   // the wheel's rigid body
  int carrier = -1;                // the body its axle belongs to; -1: a lone wheel (drive
                                   // torque is then external, and there is nothing to brake against)
  Vec3 axis = Vec3::UnitY();       // unit, wheel frame: positive spin drives forward
  double radius = 1.0;             // m
  WheelContact contact = WheelContact::RimPoints;
  bool steerable = false;
  double max_steer = 0.0;          // rad
  double steer_rate = 1.0;         // rad/s   fastest change of the steering angle
  int first_point = 0;             // its rim points: [first_point, first_point + rim_points)
  int rim_points = 0;
};

struct Model;
double groundStiffness(const Model& m, int body);  // per contact point of `body` (-1: a particle)
double groundDamping(const Model& m, int body);

struct Model {
  Options opt;
  GroundPtr ground;
  std::vector<Body> bodies;
  std::vector<Particle> particles;
  std::vector<Point> points;
  std::vector<Spring> springs;
  std::vector<Wheel> wheels;
  std::vector<int> contact_points;  // indices of points with contact = true
  // derived at build, for the hot loops: a body's points are contiguous
  std::vector<int> body_point_begin, body_point_end;  // (nbody)
  std::vector<int> steered_points;    // points that turn with a wheel's steering
  std::vector<int> particle_points;   // point index of each particle
  // Springs [first, first + count) whose `a` points are consecutive and
  // whose `b` point is shared (a wheel rim fanned out to one axle point):
  // their loop runs over contiguous arrays and vectorises. The rest go one
  // by one.
  struct SpringFan { int first = 0, count = 0, a0 = 0, b = 0; };
  std::vector<SpringFan> spring_fans;
  std::vector<int> loose_springs;
  std::vector<double> spring_k, spring_c, spring_rest;  // (nspring) copies for the fan loop
  std::vector<std::string> vehicle_names;
  std::vector<int> vehicle_of_wheel;  // which vehicle each wheel belongs to
  std::vector<int> vehicle_body;      // the chassis body of each vehicle
  std::vector<RoadCar> road_cars;     // road_car.hpp; their states follow the particles in y
  int aux_states = 0;                 // kRoadCarStates per road car
  // contact between bodies (collision/collision.hpp): groups in build
  // order (vehicles, then objects); their colliders and probes contiguous
  std::vector<CollisionGroup> groups;
  std::vector<Collider> colliders;
  std::vector<Probe> probes;
  std::vector<ProbeChunk> probe_chunks;  // each rigid or static group's probes in runs, in order
  std::vector<SceneObject> objects;   // obstacles: static (body -1) or with mass
  // collisions on, and two groups of which one can move: the step runs the
  // broad phase (and takes the general loop while a pair may touch)
  bool collisions = false;
  int object_substeps = 1;            // substeps objects' ground contact needs (collision_build.cpp)

  int auxBase() const { return 13 * static_cast<int>(bodies.size()) + 6 * static_cast<int>(particles.size()); }
  int stateSize() const { return auxBase() + aux_states; }
};

inline double groundStiffness(const Model& m, int body) {
  return body >= 0 && m.bodies[body].ground_stiffness > 0.0 ? m.bodies[body].ground_stiffness : m.opt.contact.stiffness;
}
inline double groundDamping(const Model& m, int body) {
  return body >= 0 && m.bodies[body].ground_damping >= 0.0 ? m.bodies[body].ground_damping : m.opt.contact.damping;
}

}  // namespace groundsim
