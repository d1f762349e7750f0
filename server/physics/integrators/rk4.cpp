// Classic Runge-Kutta 4 on the flat state (see integrator_methods.hpp). Every stage
// passes the full step h to computeForces: velocity-level friction and brakes
// then act as a relaxation of rate 1/h, which RK4's stability region holds.
#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"

namespace groundsim {

void Rk4::advance(const Model& m, State& s, Workspace& ws, double h) {
  Eigen::VectorXd& y = s.y;
  Eigen::VectorXd& yt = ws.ytmp;
  auto stage = [&](const Eigen::VectorXd& at, Eigen::VectorXd& k) {
    computeForces(m, at, s.applied, h, ws);
    stateDerivative(m, at, ws, k);
    ++evaluations;
    return ws.drive_power;
  };
  const double p1 = stage(y, ws.k1);
  yt = y + (0.5 * h) * ws.k1;
  const double p2 = stage(yt, ws.k2);
  yt = y + (0.5 * h) * ws.k2;
  const double p3 = stage(yt, ws.k3);
  yt = y + h * ws.k3;
  const double p4 = stage(yt, ws.k4);
  y += (h / 6.0) * (ws.k1 + 2.0 * ws.k2 + 2.0 * ws.k3 + ws.k4);
  normalizeRotations(m, y);
  // the drive work with the method's own quadrature weights
  s.drive_work += (h / 6.0) * (p1 + 2.0 * p2 + 2.0 * p3 + p4);
}

}  // namespace groundsim
