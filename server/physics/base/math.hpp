// Small vector/rotation helpers shared by the physics core (Eigen only).
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "physics/base/pointwise.hpp"

namespace groundsim {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Rotation by the rotation vector w (axis * angle): Rodrigues' formula as a
// quaternion, exact for any angle. The report's eq. (12) applies the same map
// to every point offset; rotating the orientation once is equivalent and
// cannot stretch the body (the report's code used u'*u where u*u' was meant).
inline Quat rotationFromVector(const Vec3& w) {
  const double a2 = w.squaredNorm();
  if (a2 < pointwise::kRotationSeries) {
    // per-step angles are tiny (a wheel at 5 rad/s turns 2.5e-4 rad in
    // 5e-5 s): the series every step path takes (pointwise.hpp)
    double c, s;
    pointwise::halfAngleSeries(a2, c, s);
    return Quat(c, s * w.x(), s * w.y(), s * w.z());
  }
  const double angle = std::sqrt(a2);
  return Quat(Eigen::AngleAxisd(angle, w / angle));
}

// q advanced by a constant world-frame angular velocity omega over h.
inline Quat integrateRotation(const Quat& q, const Vec3& omega, double h) {
  return (rotationFromVector(omega * h) * q).normalized();
}

}  // namespace groundsim
