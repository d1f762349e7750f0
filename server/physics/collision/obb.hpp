// Oriented boxes for the broad phase's closer check: two cars side by side
// in neighbouring lanes have overlapping bounding spheres but boxes metres
// apart, and a pair that passes costs the narrow phase and contact substeps.
#pragma once

#include <cmath>

#include "physics/base/math.hpp"

namespace groundsim {

struct OrientedBox {
  Vec3 c = Vec3::Zero();           // m  centre (world)
  Mat3 R = Mat3::Identity();       // box axes as columns (box -> world)
  Vec3 h = Vec3::Zero();           // m  half extents along those axes
};

// Separating axis test over the 15 axes of two boxes (the three face normals
// of each and their nine cross products). The epsilon keeps near-parallel
// edges' cross products, which are almost zero, from declaring a separation.
inline bool overlap(const OrientedBox& a, const OrientedBox& b) {
  const Mat3 R = a.R.transpose() * b.R;
  const Vec3 t = a.R.transpose() * (b.c - a.c);
  const Mat3 A = R.cwiseAbs().array() + 1e-9;
  for (int i = 0; i < 3; ++i)
    if (std::abs(t[i]) > a.h[i] + A.row(i).dot(b.h)) return false;
  for (int j = 0; j < 3; ++j)
    if (std::abs(t.dot(R.col(j))) > a.h.dot(A.col(j)) + b.h[j]) return false;
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = a.h[i1] * A(i2, j) + a.h[i2] * A(i1, j);
      const double rb = b.h[j1] * A(i, j2) + b.h[j2] * A(i, j1);
      if (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) > ra + rb) return false;
    }
  }
  return true;
}

// Whether a point lies in the box grown by `pad` on every side.
inline bool contains(const OrientedBox& b, const Vec3& p, double pad) {
  const Vec3 q = (b.R.transpose() * (p - b.c)).cwiseAbs();
  return (q.array() <= b.h.array() + pad).all();
}

}  // namespace groundsim
