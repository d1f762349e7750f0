// Integrators advance a State by one step h. They see the physics only
// through computeForces / stateDerivative, so each one is a short file.
#pragma once

#include <memory>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Advances s.y by h (s.t and s.tick are the caller's). Adaptive methods
  // take as many internal steps as their tolerance needs to cover h.
  virtual void advance(const Model& m, State& s, Workspace& ws, double h) = 0;
  virtual const char* name() const = 0;
  // true: advance() applies the commanded controls itself (applyControls,
  // over each of its substeps); false: the caller applies them once per step
  virtual bool appliesControls() const { return false; }
  // force evaluations so far (the cost measure of the accuracy benchmark)
  long long evaluations = 0;
};

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind);

// Whether the integrator can integrate the friction model at its order.
// Semi-implicit Euler and velocity Verlet are time-steppers that own the
// velocity-level stick-slip solve (and take sign friction as the report
// did). RK4, adaptive and implicit Euler integrate an ODE y' = f(y): the
// stick-slip impulses depend on the step (a stage of RK4 or a trial step
// of the adaptive method changes them) and sign friction is discontinuous at
// zero slip, so with either they fall to order 1-2 on a car; they need the
// smooth (regularized) friction. Returns the reason for a refused
// combination, or nullptr. The scenario layer reports it at
// /contact/friction_model.
const char* integratorFrictionConflict(IntegratorKind kind, FrictionModel friction);
const char* integratorName(IntegratorKind kind);

// Shared by the explicit integrators: after a full-vector update the
// quaternions must be unit again.
void normalizeRotations(const Model& m, Eigen::VectorXd& y);

}  // namespace groundsim
