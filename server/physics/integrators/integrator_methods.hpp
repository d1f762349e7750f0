// The concrete integrators (one .cpp each) and the helpers they share.
// The interface, the factory and the names are in integrator.hpp; all their
// scratch lives in the Workspace (workspace.hpp), so an Integrator object
// holds only its statistics.
#pragma once

#include <vector>

#include "physics/integrators/integrator.hpp"

namespace groundsim {

class SemiImplicitEuler final : public Integrator {
 public:
  void advance(const Model& m, State& s, Workspace& ws, double h) override;
  const char* name() const override { return "semi_implicit_euler"; }
};

}  // namespace groundsim

// ---- the speed/accuracy alternatives (issue 4) ----

namespace groundsim {

// Kick-drift-kick on the momenta v and L, drifting positions with the
// half-step velocity and orientations with the same implicit-midpoint
// rotation as SemiImplicitEuler. Second order for forces that depend on
// positions only (first order once damping or friction read velocities);
// symplectic, stable for omega h < 2. Each kick is a velocity update over
// h/2, so velocity-level friction and brakes are sized for h/2: the stick
// impulse then cancels the slip at the end of each kick, as in SIE.
class VelocityVerlet final : public Integrator {
 public:
  void advance(const Model& m, State& s, Workspace& ws, double h) override;
  const char* name() const override { return "velocity_verlet"; }
};

// Classic fourth-order Runge-Kutta on the flat state vector, quaternions
// renormalised after the step. Stable for omega h < 2.83 (undamped).
class Rk4 final : public Integrator {
 public:
  void advance(const Model& m, State& s, Workspace& ws, double h) override;
  const char* name() const override { return "rk4"; }
};

// Linearly implicit (backward) Euler, as Baraff and Witkin do for cloth:
// y+ = y + h (I - h J)^-1 f(y), J = df/dy by one-sided finite differences of
// the full derivative, one column per state component. Unconditionally
// stable for stiff springs and grounds, first order, and dissipative
// (a bounce loses energy at large omega h). Costs n + 1 force evaluations
// and an n x n LU per step: for small scenes with stiff parts.
class ImplicitEuler final : public Integrator {
 public:
  void advance(const Model& m, State& s, Workspace& ws, double h) override;
  const char* name() const override { return "implicit_euler"; }
};

// Bogacki-Shampine 3(2) with first-same-as-last, error-controlled by
// Options.tolerance (mixed absolute/relative, max norm over components).
// Covers exactly h per advance in internal substeps, starting from
// s.h_next and storing the next trial step back into it, so a saved State
// continues bit for bit.
class Adaptive final : public Integrator {
 public:
  void advance(const Model& m, State& s, Workspace& ws, double h) override;
  const char* name() const override { return "adaptive"; }
  // its controls follow its substeps: steering at its rate, the gear's timer
  bool appliesControls() const override { return true; }
  long long accepted = 0, rejected = 0;  // substep statistics
};

// ---- helpers shared by the integrators (integrator.cpp) ----

// q0 advanced over h by the angular velocity at the half-step orientation,
// omega = R I^-1 R^T L (implicit midpoint by fixed-point passes, starting
// from omega0, the angular velocity at q0): keeps a free body's energy and
// precession right, unlike the start-of-step inertia. Semi-implicit Euler
// takes one pass, velocity Verlet two.
Quat rotateMidpoint(const Quat& q0, const Mat3& inv_inertia_body, const Vec3& omega0, const Vec3& L,
                    double h, int passes);
// Semi-implicit Euler's update of body i (report eqs. 18-21): momenta by
// dv and dL, then the position with the new velocity and the orientation
// by the midpoint rotation (one pass) from inv_inertia_world, the world
// inverse inertia at the start of the update.
void semiImplicitBodyUpdate(const Model& m, Eigen::VectorXd& y, int i, const Vec3& dv, const Vec3& dL,
                            const Mat3& inv_inertia_world, double h);
// semiImplicitBodyUpdate of every body under the evaluation's forces in
// ws (but those marked in skip, when given), then the particles'
// momenta and positions.
void semiImplicitBodiesAndParticles(const Model& m, Eigen::VectorXd& y, const Workspace& ws, double h,
                                    const unsigned char* skip = nullptr);
// omega = R I^-1 R^T L at orientation q.
Vec3 angularVelocityAt(const Quat& q, const Mat3& inv_inertia_body, const Vec3& L);

// True when the last force evaluation in ws depended on the step h passed to
// computeForces: stick-slip contacts with friction, or brakes.
bool forcesDependOnStep(const Model& m, const std::vector<WheelControl>& applied, const Workspace& ws);
// Whether any contact of the last evaluation has friction (its own mu, which
// friction by place sets per contact).
bool contactsHaveFriction(const Workspace& ws);

}  // namespace groundsim
