#include "physics/forces/forces.hpp"

#include <algorithm>

#include "physics/forces/body_contact.hpp"
#include "physics/forces/road_car_phase.hpp"

namespace groundsim {

void computeForces(const Model& m, const Eigen::VectorXd& y,
                   const std::vector<WheelControl>& controls, double h, Workspace& ws) {
  // 4.1: where every point is and how fast it moves
  computeKinematics(m, y, controls, ws);
  // 4.2: forces, each kind into its own buffer
  applySprings(m, ws);
  detectGroundContacts(m, ws);
  applyContactNormals(m, ws);
  applyExplicitFriction(m, ws);      // regularised / sign models only
  accumulateBodyForces(m, ws);       // gravity + point forces -> body force and torque
  if (ws.defer_body_contacts) clearBodyContacts(ws);  // the contact phase's own (integrators/contact_phase.cpp)
  else bodyContacts(m, true, ws);    // bodies touching bodies (forces/body_contact.cpp)
  ws.max_depth = std::max(ws.max_depth, ws.body_contact_depth);
  applyDrive(m, controls, ws);       // drive torque on wheel, reaction on carrier
  if (!velocityLevelBrakes(m)) applyRegularizedBrakes(m, controls, ws);
  applyRoadCars(m, y, h, ws);        // tyres, suspension, powertrain, brakes, drag (road_cars.cpp)
  // stick-slip friction and brakes need the velocities the other forces are
  // about to produce, so they come last
  solveVelocityConstraints(m, y, controls, h, ws);
}

void stateDerivative(const Model& m, const Eigen::VectorXd& y, const Workspace& ws,
                     Eigen::VectorXd& dy) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    const Quat q = bodyRot(y, i);
    const Vec3& w = ws.omega[i];
    // q' = 1/2 (0, w) q, with w in the world frame
    const Quat wq(0.0, w.x(), w.y(), w.z());
    const Quat qd = wq * q;
    bodyPos(dy, i) = bodyVel(y, i);
    bodyRot(dy, i).coeffs() = 0.5 * qd.coeffs();
    bodyVel(dy, i) = ws.body_force[i] / m.bodies[i].mass;
    bodyMom(dy, i) = ws.body_torque[i];
  }
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j) {
    const int o = particleOffset(nb, j);
    dy.segment<3>(o) = y.segment<3>(o + 3);
    dy.segment<3>(o + 3) = ws.particle_force[j] / m.particles[j].mass;
  }
  if (m.aux_states > 0) dy.tail(m.aux_states) = ws.aux_dot;
}

}  // namespace groundsim
