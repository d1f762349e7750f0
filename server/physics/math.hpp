// Small vector/rotation helpers shared by the physics core (Eigen only).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

namespace groundsim {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Rotation by the rotation vector w (axis * angle): Rodrigues' formula as a
// quaternion, exact for any angle. The report's eq. (12) applies the same map
// to every point offset; rotating the orientation once is equivalent and
// cannot stretch the body (the report's code used u'*u where u*u' was meant).
inline Quat rotationFromVector(const Vec3& w) {
  const double angle = w.norm();
  if (angle < 1e-12) {
    // second-order series keeps the map smooth through zero
    Quat q(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z());
    return q.normalized();
  }
  const Vec3 axis = w / angle;
  return Quat(Eigen::AngleAxisd(angle, axis));
}

// q advanced by a constant world-frame angular velocity omega over h.
inline Quat integrateRotation(const Quat& q, const Vec3& omega, double h) {
  return (rotationFromVector(omega * h) * q).normalized();
}

inline Mat3 skew(const Vec3& v) {
  Mat3 s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

}  // namespace groundsim
