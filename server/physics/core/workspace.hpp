// All scratch of one simulation, sized once for a model so that step()
// never allocates: what one force evaluation computes (grouped by the phase
// that fills it; per-kind force buffers stay separate until summed so
// telemetry and tests can read them), the ground's evaluator, the
// integrators' scratch, the rollback copy, and a separate scratch for the
// diagnostics so that sampling energy never overwrites the step's buffers.
// Nothing here is part of the model: one Model serves many Workspaces.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "physics/collision/obb.hpp"
#include "physics/core/model.hpp"
#include "physics/core/state.hpp"

namespace groundsim {

struct Contact {
  int point = -1;     // point index (rim/body/particle contact), or -1 for a wheel circle
  int body = -1;      // body that receives the force, or -1
  int particle = -1;  // particle that receives the force, or -1
  int wheel = -1;     // wheel it belongs to, or -1
  Vec3 p, n, r;       // world point, unit ground normal, offset from the body COM
  double depth = 0.0; // m, > 0 below the ground
  double normal = 0.0;// N, normal force magnitude (>= 0)
  double mu = 0.0;    // -, Coulomb friction at p (Ground::friction)
  Vec3 friction = Vec3::Zero();  // N, tangential force
  Vec3 u = Vec3::Zero();         // m/s, velocity of the point
  Vec3 slip = Vec3::Zero();      // m/s, tangential part of u
  // velocity-level friction: tangent basis t, a = r x t, b = I^-1 a (so an
  // impulse d1 t1 + d2 t2 turns the body by d1 b1 + d2 b2), inverse
  // effective mass in the tangent plane, accumulated impulse
  Vec3 t1, t2, a1, a2, b1, b2;
  Eigen::Matrix2d k, k_inv;
  Eigen::Vector2d impulse;
};

struct Workspace {
  // with_diagnostics: also build the diagnostics' own scratch (a Workspace
  // of its own, without one in turn)
  explicit Workspace(const Model& m, bool with_diagnostics = true);
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  Workspace(Workspace&&) = default;
  Workspace& operator=(Workspace&&) = default;

  // the ground with this simulation's evaluation state (a parser's variables)
  GroundProbe ground;

  // kinematics (report section 4.1): rotations and world points
  std::vector<Mat3> R;                 // (nbody) body to world
  std::vector<Mat3> inv_inertia_world; // (nbody) R I^-1 R^T
  std::vector<Vec3> com;               // (nbody) m, centre of mass
  std::vector<Vec3> vel;               // (nbody) m/s
  std::vector<Vec3> omega;             // (nbody) rad/s, world
  // points as structure of arrays so the per-body loops vectorise
  std::vector<double> lx, ly, lz;      // (npoint) m, body-frame offsets (steering applied)
  std::vector<double> px, py, pz;      // (npoint) m, world position
  std::vector<double> ux, uy, uz;      // (npoint) m/s, world velocity
  std::vector<double> H;               // (npoint) ground function at the point
  Vec3 pointPos(int k) const { return Vec3(px[k], py[k], pz[k]); }
  Vec3 pointVel(int k) const { return Vec3(ux[k], uy[k], uz[k]); }
  Vec3 springForce(int k) const { return Vec3(fx[k], fy[k], fz[k]); }
  std::vector<unsigned char> body_far; // (nbody) broad phase: provably above the ground

  // forces (report section 4.2), each kind in its own buffer
  std::vector<double> fx, fy, fz;      // (npoint) N, spring forces
  std::vector<Contact> contacts;       // capacity: contact points + wheels
  int ncontacts = 0;
  std::vector<Vec3> body_force;        // (nbody) N, total
  std::vector<Vec3> body_torque;       // (nbody) N m, total about the COM
  std::vector<Vec3> particle_force;    // (nparticle) N, total

  // velocity-level pass (friction, brakes): predicted velocities
  std::vector<Vec3> v_pred, w_pred;    // (nbody)
  std::vector<Vec3> pv_pred;           // (nparticle)
  std::vector<double> brake_impulse;   // (nwheel) N m s

  // telemetry of the last evaluation
  std::vector<double> wheel_normal;    // (nwheel) N
  std::vector<double> wheel_friction;  // (nwheel) N
  std::vector<double> wheel_slip;      // (nwheel) m/s, largest contact slip
  double ground_energy = 0.0;          // J, penalty energy 1/2 S depth^2
  double max_depth = 0.0;              // m
  double drive_power = 0.0;            // W
  int friction_sweeps = 0;             // Gauss-Seidel sweeps the last evaluation needed

  // contact between bodies (forces/body_contact.cpp)
  std::vector<Vec3> group_lo, group_hi;  // (ngroup) m, world boxes this evaluation
  std::vector<Vec3> group_com;         // (ngroup) m, reference body's COM (static: box centre)
  std::vector<OrientedBox> group_box;  // (ngroup) movable groups' oriented boxes, padded
  std::vector<double> group_pad;       // (ngroup) m, padding for the motion in the step
  std::vector<int> sweep;              // groups sorted by group_lo.x (kept between steps)
  std::vector<std::pair<int, int>> pairs;  // candidate pairs of the broad phase
  // set by the Simulator for the length of one step: `pairs` came from
  // groupsMayTouch at the step's start, its boxes padded by what each group
  // can move in the step, so the step's force evaluations skip the sweep
  bool step_pairs = false;
  // set with step_pairs by contactSubsteps: for each pair of two rigid (or
  // static) groups, the probes its census at the step's start found
  // pressing or within the step's reach of a shape of the other group, as
  // (probe, collider) in the order the narrow phase visits them; the step's
  // force evaluations test only these (body_contact.cpp)
  struct CensusProbe {
    int probe, collider;
  };
  bool step_census = false;
  std::vector<CensusProbe> census;                  // pair by pair
  std::vector<std::array<int, 3>> census_range;     // (pairs) [begin, mid, end): a's probes, b's; begin -1: none
  // the contact phase (integrators/contact_phase.cpp): computeForces
  // leaves contact between bodies out while it is set; per car of the
  // step's pairs its road car index and the forces and travel accelerations
  // held over the phase's substeps
  bool defer_body_contacts = false;
  std::vector<int> phase_cars;
  std::vector<unsigned char> in_phase;                // (nbody)
  std::vector<Vec3> phase_force, phase_torque;        // (phase_cars)
  std::vector<std::array<double, 4>> phase_travel;    // (phase_cars) m/s^2
  std::vector<PairContact> pair_contacts;  // pairs in contact, last evaluation
  double body_contact_energy = 0.0;    // J, 1/2 S depth^2 over probes inside shapes
  double body_contact_depth = 0.0;     // m, deepest probe

  // road cars (forces/road_cars.cpp): per-step inputs, per-evaluation outputs, state rates
  std::vector<CarRuntime> car_inputs;  // (nroadcar)
  // the controls before an adaptive substep (applied, cars), restored when it is rejected
  std::vector<WheelControl> applied_mark;  // (nwheel)
  std::vector<CarRuntime> cars_mark;       // (nroadcar)
  std::vector<RoadCarOut> road;        // (nroadcar)
  Eigen::VectorXd aux_dot;             // (aux_states)

  // integrator scratch
  Eigen::VectorXd dy, ytmp, k1, k2, k3, k4, k5, k6, k7, err;
  // implicit Euler only (n x n, so left empty for the others): the Jacobian,
  // I - h J and its factorisation, and the finite-difference scale per
  // state component (positions and velocities on a metre scale,
  // quaternions on 1, angular momenta on the body's largest inertia)
  Eigen::MatrixXd jac, lhs;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  Eigen::VectorXd fd_scale;
  // velocity Verlet's end-of-step forces, reused as the next step's start
  // forces while they are valid (see velocity_verlet.cpp)
  struct VerletCache {
    bool valid = false;
    Eigen::VectorXd y;
    std::vector<WheelControl> controls;
    std::vector<Vec3> force, torque, particle_force;
  } verlet;

  // the state before the current step, restored whole on divergence
  State last_good;

  // the diagnostics' scratch (energy): never the buffers above
  std::unique_ptr<Workspace> diagnostics;
};

}  // namespace groundsim
