// Contact between bodies (issue 19): the model's part. Every body of a
// vehicle or an object belongs to a collision group; groups never touch
// themselves. A group carries colliders (shapes fixed to its bodies, or to
// the world for a static object) and probes (points, or a wheel's circle,
// that feel the colliders of other groups). A probe inside another group's
// collider gets the report's eq. (10) with that shape as the ground: a
// penalty force along the shape's normal plus damping, and Coulomb
// friction on the velocity relative to the shape at that point; the equal
// and opposite force and its torque go to the shape's body.
#pragma once

#include <string>
#include <vector>

#include "physics/base/math.hpp"
#include "physics/collision/shape.hpp"

namespace groundsim {

// Contacts between bodies and objects' ground contacts are resolved with
// integrator substeps where needed: omega h at most kStepMargin times the
// symplectic Euler limit of a damped oscillator, 2 (sqrt(1 + zeta^2) -
// zeta), and at most kMaxContactSubsteps of them.
inline constexpr double kStepMargin = 0.5;
inline constexpr int kMaxContactSubsteps = 64;
// Substeps of dt that resolve an oscillator of frequency omega and damping
// ratio zeta (at least 1).
int substepsFor(double omega, double zeta, double dt);

struct CollisionParams {
  bool enabled = true;              // false: bodies pass through each other
  // per probe inside a shape: stiffness S (N/m) and Kelvin-Voigt damping c
  // (N s/m). 0 / < 0: derived per pair from its reduced mass m_r so that
  // four probes in contact ring at `frequency` with `damping_ratio`:
  // S = m_r (2 pi f)^2 / 4, c = zeta sqrt(S m_r)
  double stiffness = 0.0;           // N/m
  double damping = -1.0;            // N s/m
  double frequency = 30.0;          // Hz
  double damping_ratio = 0.3;       // -
  double friction = 0.5;            // -      Coulomb mu of vehicles (objects carry their own)
  double slip_velocity = 0.05;      // m/s    friction is mu N tanh(|slip| / v_s)
  double probe_spacing = 0.5;       // m      largest gap between a shape's probe points
  // a hit is hard once the velocity change it gave the lighter vehicle of
  // the pair (else the lighter object) exceeds this: crash severity as
  // delta-v, which does not depend on the penalty's stiffness (a peak
  // force does: a stiff contact makes every bump tens of g)
  double hard_impact_dv = 5.0;      // m/s
  // at least this many integrator substeps per step while bodies may touch
  // (and for objects resting on the ground): the automatic count keeps the
  // contact stable, and stops refining it once the step is below what
  // stability asks; a fixed floor makes the contact's substep shrink with
  // the step, so halving dt halves it too (accuracy/pilot.hpp uses this)
  int min_substeps = 1;
};

struct Collider {
  int group = -1;
  int body = -1;                    // -1: static, pose in the world frame
  Shape shape;
  Vec3 pos = Vec3::Zero();          // m      shape origin in the body's COM frame (or world)
  Mat3 rot = Mat3::Identity();      // shape frame -> body frame (or world)
};

struct Probe {
  int group = -1;
  int body = -1;                    // body it moves with, or -1 (a particle, or static)
  int particle = -1;                // particle it is, or -1
  int point = -1;                   // model point it is (position from the kinematics), or -1
  Vec3 local = Vec3::Zero();        // m      offset from the body's COM in its frame (world if static)
  int wheel = -1;                   // >= 0: the circle of this wheel (centre at its body's COM)
};

// A run of a rigid or static group's probes (contiguous, in their order)
// and the box holding their positions in the reference body's frame about
// its COM (a static group's: the world), with 1 nm to spare for round-off:
// the census skips a run whose box misses a shape's.
struct ProbeChunk {
  int begin = 0, end = 0;
  Vec3 c = Vec3::Zero(), h = Vec3::Zero();  // m  centre and half extents
};
inline constexpr int kProbeChunk = 8;  // probes per run (the last may hold fewer)

struct CollisionGroup {
  std::string name;
  double mass = 0.0;                // kg     0: static (immovable)
  int ref_body = -1;                // body whose COM centres the group's bound; -1: static
  double bound = 0.0;               // m      radius about that COM holding every probe and shape
  // a box in the reference body's frame, about its COM, holding every probe
  // and shape with the bound's margin: the broad phase's closer check
  Vec3 box_c = Vec3::Zero(), box_h = Vec3::Zero();  // m  centre and half extents
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // m  static groups: world box
  // every probe and shape fixed to the reference body (a road car, an
  // object with mass): box_c, box_h hold them exactly, with no margin
  bool rigid = false;
  double friction = 0.5;            // -      Coulomb mu; a pair uses sqrt(mu_a mu_b)
  int probe_begin = 0, probe_end = 0;
  int collider_begin = 0, collider_end = 0;
  int chunk_begin = 0, chunk_end = 0;  // its runs of probes (Model::probe_chunks): rigid and static groups
  // most probes that can press on one plane at once (those on one side of
  // the group, to 2% of its size): bounds the pair's contact frequency
  int face_probes = 1;
  int object = -1;                  // index among the scene's objects, or -1 (a vehicle)
  int vehicle = -1;                 // vehicle index, or -1 (an object)
};

// An obstacle of the scenario's `objects`: static, or a body of its own.
struct SceneObject {
  std::string name;
  int body = -1;                    // -1: static
  int group = -1;
  Shape shape;
  Vec3 pos = Vec3::Zero();          // m      shape origin: world (static) or in the body's COM frame
  Mat3 rot = Mat3::Identity();      // shape frame -> world (static) or body frame
};

// One pair of groups in contact at the last force evaluation: telemetry.
struct PairContact {
  int a = -1, b = -1;               // groups, a < b
  int points = 0;                   // probes inside
  Vec3 force = Vec3::Zero();        // N      on a, by b (normal and friction)
  Vec3 where = Vec3::Zero();        // m      normal-force-weighted mean of the probe points
  double normal = 0.0;              // N      sum of normal forces
  double depth = 0.0;               // m      deepest probe
};

}  // namespace groundsim
