// Linearly implicit Euler (Baraff & Witkin 1998): one Newton step of
// backward Euler, y+ = y + h (I - h J)^-1 f(y), J = df/dy at y.
//
// J is taken by finite differences of the whole derivative (forces,
// contacts, friction, kinematics), so every force kind is covered without
// hand-written Jacobians. Each column perturbs one component by
// sqrt(eps) times its typical magnitude: positions and velocities on a
// metre scale, quaternion components on 1, angular momenta on the body's
// largest principal inertia times 1 rad/s (a 0.1 kg wheel's L is small, and
// a perturbation sized for metres would swamp it).
#include <cfloat>
#include <cmath>

#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"

namespace groundsim {

void ImplicitEuler::advance(const Model& m, State& s, Workspace& ws, double h) {
  const int n = m.stateSize();
  // the matrices, their factorisation and fd_scale were sized by the Workspace
  Eigen::VectorXd& y = s.y;
  Eigen::VectorXd& yp = ws.ytmp;
  computeForces(m, y, s.applied, h, ws);
  stateDerivative(m, y, ws, ws.k1);
  ++evaluations;
  const double power = ws.drive_power;

  yp = y;
  const double root_eps = std::sqrt(DBL_EPSILON);
  for (int j = 0; j < n; ++j) {
    const double yj = y[j];
    // a representable step, so (f(y + d) - f(y)) / d divides by what was added
    const double d = (yj + root_eps * std::max(std::abs(yj), ws.fd_scale[j])) - yj;
    yp[j] = yj + d;
    computeForces(m, yp, s.applied, h, ws);
    stateDerivative(m, yp, ws, ws.k2);
    ++evaluations;
    ws.jac.col(j) = (ws.k2 - ws.k1) / d;
    yp[j] = yj;
  }
  ws.lhs.noalias() = -h * ws.jac;
  ws.lhs.diagonal().array() += 1.0;
  ws.lu.compute(ws.lhs);
  ws.dy.noalias() = ws.lu.solve(ws.k1);
  y += h * ws.dy;
  normalizeRotations(m, y);
  s.drive_work += h * power;
}

}  // namespace groundsim
