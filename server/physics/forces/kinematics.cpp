// Report section 4.1: world position and velocity of every point from the
// body poses. The world inertia is rotated here, every evaluation
// (I_w = R I_b R^T); the report's code kept the initial one.
#include "physics/forces/forces.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim {

namespace {

GROUNDSIM_INLINE_BODY void kinematicsBody(const Model& m, const Eigen::VectorXd& y,
                                          const std::vector<WheelControl>& controls, Workspace& ws) {
  // steering turns axle points about the vertical of their body frame
  for (int k : m.steered_points) {
    const Point& pt = m.points[k];
    const double a = controls[pt.steer_wheel].steer;
    const double c = a == 0.0 ? 1.0 : std::cos(a), s = a == 0.0 ? 0.0 : std::sin(a);  // straight ahead: no trig
    const Vec3 d = pt.local - pt.steer_pivot;
    ws.lx[k] = pt.steer_pivot.x() + c * d.x() - s * d.y();
    ws.ly[k] = pt.steer_pivot.y() + s * d.x() + c * d.y();
  }
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    bodyFrame(m, y, i, ws);
    const Mat3 R = ws.R[i];
    // p = c + R l ; u = v + w x (R l), branch-free over the body's points
    const double r00 = R(0, 0), r01 = R(0, 1), r02 = R(0, 2), r10 = R(1, 0), r11 = R(1, 1),
                 r12 = R(1, 2), r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2);
    const double cx = ws.com[i].x(), cy = ws.com[i].y(), cz = ws.com[i].z();
    const double vx = ws.vel[i].x(), vy = ws.vel[i].y(), vz = ws.vel[i].z();
    const double wx = ws.omega[i].x(), wy = ws.omega[i].y(), wz = ws.omega[i].z();
    const double* __restrict lx = ws.lx.data();
    const double* __restrict ly = ws.ly.data();
    const double* __restrict lz = ws.lz.data();
    double* __restrict px = ws.px.data();
    double* __restrict py = ws.py.data();
    double* __restrict pz = ws.pz.data();
    double* __restrict ux = ws.ux.data();
    double* __restrict uy = ws.uy.data();
    double* __restrict uz = ws.uz.data();
    const int kb = m.body_point_begin[i], ke = m.body_point_end[i];
#pragma omp simd
    for (int k = kb; k < ke; ++k) {
      const double rx = r00 * lx[k] + r01 * ly[k] + r02 * lz[k];
      const double ry = r10 * lx[k] + r11 * ly[k] + r12 * lz[k];
      const double rz = r20 * lx[k] + r21 * ly[k] + r22 * lz[k];
      px[k] = cx + rx;
      py[k] = cy + ry;
      pz[k] = cz + rz;
      ux[k] = vx + wy * rz - wz * ry;
      uy[k] = vy + wz * rx - wx * rz;
      uz[k] = vz + wx * ry - wy * rx;
    }
  }
  for (size_t j = 0; j < m.particles.size(); ++j) {
    const int k = m.particle_points[j];
    const int o = particleOffset(nb, static_cast<int>(j));
    ws.px[k] = y[o];
    ws.py[k] = y[o + 1];
    ws.pz[k] = y[o + 2];
    ws.ux[k] = y[o + 3];
    ws.uy[k] = y[o + 4];
    ws.uz[k] = y[o + 5];
  }
}


GROUNDSIM_WIDE void kinematicsWide(const Model& m, const Eigen::VectorXd& y,
                                   const std::vector<WheelControl>& controls, Workspace& ws) {
  kinematicsBody(m, y, controls, ws);
}
void kinematicsGeneric(const Model& m, const Eigen::VectorXd& y,
                       const std::vector<WheelControl>& controls, Workspace& ws) {
  kinematicsBody(m, y, controls, ws);
}

}  // namespace

void computeKinematics(const Model& m, const Eigen::VectorXd& y,
                       const std::vector<WheelControl>& controls, Workspace& ws) {
  if (useWideSimd(m.opt.deterministic)) kinematicsWide(m, y, controls, ws);
  else kinematicsGeneric(m, y, controls, ws);
}

}  // namespace groundsim
