// Report section 4.1: world position and velocity of every point from the
// body poses. The world inertia is rotated here, every evaluation
// (I_w = R I_b R^T); the report's code kept the initial one.
#include "forces.hpp"

namespace groundsim {

void computeKinematics(const Model& m, const Eigen::VectorXd& y,
                       const std::vector<WheelControl>& controls, Workspace& ws) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    const Mat3 R = bodyRot(y, i).normalized().toRotationMatrix();
    ws.R[i] = R;
    ws.inv_inertia_world[i] = R * m.bodies[i].inv_inertia * R.transpose();
    ws.omega[i] = ws.inv_inertia_world[i] * bodyMom(y, i);
    ws.com[i] = bodyPos(y, i);
    ws.vel[i] = bodyVel(y, i);
  }
  const int np = static_cast<int>(m.points.size());
  for (int k = 0; k < np; ++k) {
    const Point& pt = m.points[k];
    if (pt.body >= 0) {
      Vec3 local = pt.local;
      if (pt.steer_wheel >= 0) {
        // steering turns the axle points about the vertical of the body frame
        const double a = controls[pt.steer_wheel].steer;
        const double c = std::cos(a), s = std::sin(a);
        const Vec3 d = local - pt.steer_pivot;
        local = pt.steer_pivot + Vec3(c * d.x() - s * d.y(), s * d.x() + c * d.y(), d.z());
      }
      const Vec3 r = ws.R[pt.body] * local;
      ws.point_pos[k] = ws.com[pt.body] + r;
      ws.point_vel[k] = ws.vel[pt.body] + ws.omega[pt.body].cross(r);
    } else {
      const int o = particleOffset(nb, pt.particle);
      ws.point_pos[k] = y.segment<3>(o);
      ws.point_vel[k] = y.segment<3>(o + 3);
    }
  }
}

}  // namespace groundsim
