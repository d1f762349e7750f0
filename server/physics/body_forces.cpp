// Report eqs. (7), (9), (16), (17): gravity plus every point force, summed
// into each body's force and its torque about the centre of mass.
#include "forces.hpp"

namespace groundsim {

void accumulateBodyForces(const Model& m, const Eigen::VectorXd& /*y*/, Workspace& ws) {
  const Vec3& g = m.opt.gravity;
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    ws.body_force[i] = m.bodies[i].mass * g;
    ws.body_torque[i].setZero();
  }
  for (size_t j = 0; j < m.particles.size(); ++j) ws.particle_force[j] = m.particles[j].mass * g;
  for (size_t k = 0; k < m.points.size(); ++k) {
    const Point& pt = m.points[k];
    const Vec3& f = ws.f_spring[k];
    if (pt.body >= 0) {
      ws.body_force[pt.body] += f;
      ws.body_torque[pt.body] += (ws.point_pos[k] - ws.com[pt.body]).cross(f);
    } else {
      ws.particle_force[pt.particle] += f;
    }
  }
  for (int i = 0; i < ws.ncontacts; ++i) {
    const Contact& c = ws.contacts[i];
    const Vec3 f = c.normal * c.n + c.friction;
    if (c.body >= 0) {
      ws.body_force[c.body] += f;
      ws.body_torque[c.body] += c.r.cross(f);
    } else {
      ws.particle_force[c.particle] += f;
    }
  }
}

// Drive torque about the wheel's own axle, and the equal and opposite
// reaction on its carrier (the report adds momentum to the wheels only, which
// creates angular momentum from nothing).
void applyDrive(const Model& m, const std::vector<WheelControl>& controls, Workspace& ws) {
  ws.drive_power = 0.0;
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const double T = controls[w].drive_torque;
    if (T == 0.0) continue;
    const Wheel& wh = m.wheels[w];
    const Vec3 a = ws.R[wh.body] * wh.axis;
    ws.body_torque[wh.body] += T * a;
    ws.body_torque[wh.carrier] -= T * a;
    ws.drive_power += T * a.dot(ws.omega[wh.body] - ws.omega[wh.carrier]);
  }
}

}  // namespace groundsim
