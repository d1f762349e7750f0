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

#include "forces.hpp"
#include "integrators.hpp"

namespace groundsim {

void ImplicitEuler::advance(const Model& m, State& s, Workspace& ws, double h) {
  const int n = m.stateSize();
  const int nb = static_cast<int>(m.bodies.size());
  if (scale_.size() != n) {
    // first call: size the dense matrices once (never in later calls)
    scale_.setOnes(n);
    for (int i = 0; i < nb; ++i)
      scale_.segment<3>(13 * i + 10).setConstant(std::max(m.bodies[i].inertia.diagonal().maxCoeff(), 1e-12));
    ws.jac.setZero(n, n);
    ws.lhs.setZero(n, n);
    lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
  }
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
    const double d = (yj + root_eps * std::max(std::abs(yj), scale_[j])) - yj;
    yp[j] = yj + d;
    computeForces(m, yp, s.applied, h, ws);
    stateDerivative(m, yp, ws, ws.k2);
    ++evaluations;
    ws.jac.col(j) = (ws.k2 - ws.k1) / d;
    yp[j] = yj;
  }
  ws.lhs.noalias() = -h * ws.jac;
  ws.lhs.diagonal().array() += 1.0;
  lu_.compute(ws.lhs);
  ws.dy.noalias() = lu_.solve(ws.k1);
  y += h * ws.dy;
  normalizeRotations(m, y);
  s.drive_work += h * power;
}

}  // namespace groundsim
