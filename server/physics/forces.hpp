// One force evaluation, in the order of the report's section 4:
// kinematics (4.1), forces (4.2), and the derivative the integrators use (4.3).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "model.hpp"
#include "state.hpp"
#include "workspace.hpp"

namespace groundsim {

// Fills ws with world points, every force kind, and the per-body totals at
// configuration y. h is the step the velocity-level friction and brakes act
// over (they stop slip within one step at most).
void computeForces(const Model& m, const Eigen::VectorXd& y,
                   const std::vector<WheelControl>& controls, double h, Workspace& ws);

// dy/dt at y from the totals of the last computeForces at the same y.
void stateDerivative(const Model& m, const Eigen::VectorXd& y, const Workspace& ws,
                     Eigen::VectorXd& dy);

// Phases, each in its own file.
void computeKinematics(const Model& m, const Eigen::VectorXd& y,
                       const std::vector<WheelControl>& controls, Workspace& ws);
void applySprings(const Model& m, Workspace& ws);
void detectGroundContacts(const Model& m, Workspace& ws);
void applyContactNormals(const Model& m, Workspace& ws);
void applyExplicitFriction(const Model& m, Workspace& ws);
void accumulateBodyForces(const Model& m, Workspace& ws);
void applyDrive(const Model& m, const std::vector<WheelControl>& controls, Workspace& ws);
void solveVelocityConstraints(const Model& m, const Eigen::VectorXd& y,
                              const std::vector<WheelControl>& controls, double h, Workspace& ws);

}  // namespace groundsim
