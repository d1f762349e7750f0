// Integrators advance a State by one step h. They see the physics only
// through computeForces / stateDerivative, so each one is a short file.
#pragma once

#include <memory>

#include "model.hpp"
#include "state.hpp"
#include "workspace.hpp"

namespace groundsim {

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Advances s.y by h (s.t and s.tick are the caller's). Adaptive methods
  // take as many internal steps as their tolerance needs to cover h.
  virtual void advance(const Model& m, State& s, Workspace& ws, double h) = 0;
  virtual const char* name() const = 0;
  // force evaluations so far (the cost measure of the accuracy benchmark)
  long long evaluations = 0;
};

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind);
const char* integratorName(IntegratorKind kind);

// Shared by the explicit integrators: after a full-vector update the
// quaternions must be unit again.
void normalizeRotations(const Model& m, Eigen::VectorXd& y);

}  // namespace groundsim
