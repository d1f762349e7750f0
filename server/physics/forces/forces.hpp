// One force evaluation, in the order of the report's section 4:
// kinematics (4.1), forces (4.2), and the derivative the integrators use (4.3).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim {

// Fills ws with world points, every force kind, and the per-body totals at
// configuration y. h is the step the velocity-level (stick-slip) friction
// and brakes act over (they stop slip within one step at most); with
// regularized friction the result does not depend on h, so it is a true
// right-hand side f(y) for the ODE integrators.
void computeForces(const Model& m, const Eigen::VectorXd& y,
                   const std::vector<WheelControl>& controls, double h, Workspace& ws);

// dy/dt at y from the totals of the last computeForces at the same y.
void stateDerivative(const Model& m, const Eigen::VectorXd& y, const Workspace& ws,
                     Eigen::VectorXd& dy);

// Phases, each in its own file.
// Body i's rotation, world inverse inertia, angular velocity, centre of
// mass and velocity at configuration y (the kinematics' first part).
// Always inlined, so the kinematics' wide build keeps its own arithmetic.
GROUNDSIM_INLINE_BODY void bodyFrame(const Model& m, const Eigen::VectorXd& y, int i, Workspace& ws) {
  const Mat3 R = bodyRot(y, i).normalized().toRotationMatrix();
  ws.R[i] = R;
  ws.inv_inertia_world[i] = R * m.bodies[i].inv_inertia * R.transpose();
  ws.omega[i] = ws.inv_inertia_world[i] * bodyMom(y, i);
  ws.com[i] = bodyPos(y, i);
  ws.vel[i] = bodyVel(y, i);
}

void computeKinematics(const Model& m, const Eigen::VectorXd& y,
                       const std::vector<WheelControl>& controls, Workspace& ws);
void applySprings(const Model& m, Workspace& ws);
void detectGroundContacts(const Model& m, Workspace& ws);
void applyContactNormals(const Model& m, Workspace& ws);
void applyExplicitFriction(const Model& m, Workspace& ws);
void accumulateBodyForces(const Model& m, Workspace& ws);
void applyDrive(const Model& m, const std::vector<WheelControl>& controls, Workspace& ws);
// Whether brakes are the velocity-level clamp (stick-slip and sign friction)
// rather than the smooth torque of applyRegularizedBrakes.
inline bool velocityLevelBrakes(const Model& m) {
  return m.opt.contact.friction_model != FrictionModel::Regularized;
}
// With regularized friction: each brake B exerts -B tanh(s / s_v) about its
// axle, s the wheel's spin relative to its carrier and s_v = v_s / radius
// (the spin at which the rim slips at the regularisation velocity v_s),
// reaction on the carrier. Smooth, like the friction, so a braked car is an
// ODE the higher-order integrators reach their order on.
void applyRegularizedBrakes(const Model& m, const std::vector<WheelControl>& controls, Workspace& ws);
void solveVelocityConstraints(const Model& m, const Eigen::VectorXd& y,
                              const std::vector<WheelControl>& controls, double h, Workspace& ws);

}  // namespace groundsim
