// The step of a rigid car on circle wheels, specialised for what such a
// model holds: rigid bodies, springs between body points, continuous
// wheels on a plane, stick-slip friction, semi-implicit Euler (the `fast`,
// `balanced` presets' car). No dynamic dispatch, no per-point contact
// tests, no broad phase (a circle on a plane is one closed-form point), the
// tangent basis computed once (the plane's normal is the same everywhere).
//
// The arithmetic is written once, as a template over the lane type
// (fast_car_kernel.hpp): `double` for one car (Simulator::step) and four
// doubles for four cars at once (batch_step.hpp). Both run the same
// operations in the same order, so a car stepped in a batch matches the
// same car stepped alone. Against the general force loop (forces.hpp) the
// results differ by round-off only: sums over a body's points in another
// order, and the step rotation by its series up to a^6 for step angles
// below ~0.03 rad where the general path calls sin and cos above 1e-3 rad.
#pragma once

#include <memory>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

// The model in the form the kernel reads, derived once.
struct FastCarPlan {
  struct BodyC {
    double mass, inv_mass, Ib[9];  // inverse inertia, body frame, row-major
    // Ib's shape, which picks the cheapest exact product: diagonal (the
    // principal axes), and of those symmetric about body axis `axis` (a
    // wheel about its axle: Ib = iso I + along e e^T, e that axis), whose
    // world inverse inertia is iso I + along c c^T with c = R e: no R Ib R^T.
    bool diagonal;
    int axis;                    // -1: not symmetric about a body axis
    double iso, along;
    int first_point, end_point;  // its points among `pts`
  };
  struct PointC {
    int body, model_point;
    double lx, ly, lz;       // body-frame offset (steering not applied)
    int steer_wheel;         // -1: fixed
    double pivx, pivy;       // steering pivot, and offset from it
    double dx, dy;
  };
  struct SpringC {
    int a, b;                // indices into pts
    double k, c, rest;
    bool isotropic;
  };
  struct WheelC {
    int body, carrier;
    double ax, ay, az, radius;
  };
  // A contact slot, in the general path's order: body contact points (by
  // body, then point), then one per wheel circle. A slot touches or not,
  // lane by lane.
  struct ContactC {
    int body, pt, wheel;     // pt: index into pts for a point contact, else -1
  };
  std::vector<BodyC> bodies;
  std::vector<PointC> pts;   // the points springs hang on or that touch, grouped by body
  std::vector<SpringC> springs;
  std::vector<WheelC> wheels;
  std::vector<ContactC> contacts;
  int point_contacts = 0;    // contacts[0, point_contacts) are points; wheel w is slot point_contacts + w
  double n[3], offset, gn, inv_gn;  // plane H = n . p - offset; gn = |n| as the general path computes it
  double t1[3], t2[3];       // tangent basis of the plane (Eigen's unitOrthogonal of n)
  double gravity[3];
  double stiffness, damping, mu;
  bool hunt_crossley;
  int friction_iterations;
};

// nullptr when the model can take the specialised step; otherwise why not.
// Why a model cannot take a rigid-body step path (this one or the ring
// car's) whatever its wheels: integrator, friction, particles, objects with
// mass, road cars; nullptr when none of these stands in the way.
const char* rigidStepUnsupported(const Model& m);
const char* fastCarUnsupported(const Model& m);
// A body's mass, its reciprocal and its body-frame inverse inertia, as the
// kernels read them, its shape unclassified (diagonal false, axis -1: a
// general matrix) and its point range left for the caller.
FastCarPlan::BodyC bodyConstants(const Body& b);

FastCarPlan makeFastCarPlan(const Model& m);  // requires fastCarUnsupported(m) == nullptr

// One car's specialised step, owned by its Simulator.
class FastCar {
 public:
  explicit FastCar(const Model& m);  // requires fastCarUnsupported(m) == nullptr
  ~FastCar();
  FastCar(const FastCar&) = delete;
  FastCar& operator=(const FastCar&) = delete;
  // One step of opt.dt (opt.substeps integrator steps), with the applied
  // controls already in s.applied: what Simulator::step does between
  // applyControls and checkHealth. Sets what the health check reads
  // (ws.max_depth); the rest of the workspace waits for exportTo.
  // Returns true when the new state is plainly healthy: every component
  // finite, the deepest contact and the fastest body clearly inside the
  // limits, so checkHealth (without its energy test) would pass; false
  // means only that checkHealth must decide.
  bool step(const Model& m, State& s, Workspace& ws);
  // Fills the workspace as the general force loop does for this model at
  // the last evaluation (contacts, per-wheel forces, body totals,
  // rotations, depth, broad-phase flags), so telemetry and tests read it
  // unchanged. Called on demand (Simulator::workspace): most steps nobody looks.
  void exportTo(const Model& m, Workspace& ws) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace groundsim
