// The specialised car step's lanes (fast_car_kernel.hpp): the lane types
// (`double`, one car; `v4d`, four cars), what one evaluation leaves behind
// per lane, and the small vector and rotation maths every phase uses.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "physics/base/pointwise.hpp"
#include "physics/kernels/fast_car.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim::fastcar {

using v4d = double __attribute__((vector_size(32)));
// Outside an AVX function GCC gives v4d the alignment of two SSE2 halves
// (16), inside one it moves it with 32-byte aligned loads: everything that
// holds v4d in memory is aligned to 32 explicitly (alignas below, Slot).
struct alignas(32) Slot {
  v4d v;
};

template <class V> struct Lane;
template <> struct Lane<double> {
  using M = bool;
  static constexpr int n = 1;
  GROUNDSIM_INLINE_BODY static double& at(double& v, int) { return v; }
  GROUNDSIM_INLINE_BODY static double get(double v, int) { return v; }
  GROUNDSIM_INLINE_BODY static double all(double s) { return s; }
  GROUNDSIM_INLINE_BODY static bool any(bool m) { return m; }
  GROUNDSIM_INLINE_BODY static bool andNot(bool a, bool b) { return a && !b; }
  GROUNDSIM_INLINE_BODY static double sqrt(double x) { return std::sqrt(x); }
};
template <> struct Lane<v4d> {
  using M = decltype(v4d{} < v4d{});
  static constexpr int n = 4;
  GROUNDSIM_INLINE_BODY static double& at(v4d& v, int i) { return reinterpret_cast<double*>(&v)[i]; }
  GROUNDSIM_INLINE_BODY static double get(v4d v, int i) { return v[i]; }
  GROUNDSIM_INLINE_BODY static v4d all(double s) { return v4d{s, s, s, s}; }
  GROUNDSIM_INLINE_BODY static bool any(M m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
  GROUNDSIM_INLINE_BODY static M andNot(M a, M b) { return a & ~b; }
  GROUNDSIM_INLINE_BODY static v4d sqrt(v4d x) {
    return v4d{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
  }
};

// What one evaluation leaves behind, per lane.
template <class V> struct alignas(32) BodyL {
  V R[9], Iw[9], w[3], F[3], T[3], vp[3], wp[3];
  V c[3];  // world symmetry axis (BodyC::axis >= 0); Iw is then not filled
};
template <class V> struct alignas(32) PointL {
  V r[3], p[3], u[3], f[3];
};
template <class V> struct alignas(32) ContactL {
  typename Lane<V>::M in;
  bool any_in;            // some lane touches: set once per evaluation (a mask's reduction is ~9 instructions)
  V a[3];                 // wheel axis, world (wheel slots)
  V p[3], rr[3], depth, N, u[3];
  V a1[3], a2[3], b1[3], b2[3], k00, k01, k11, i00, i01, i10, i11, j0, j1;
  V bi;                   // brake impulse
  V ia[3], ic[3], bden;   // wheel slots: the axle's inverse inertias times a, and a.(ia + ic)
};
template <class V> struct alignas(32) Held {
  V v;
};
template <class V> struct Scratch {
  explicit Scratch(const FastCarPlan& P)
      : bodies(P.bodies.size()), pts(P.pts.size()), con(P.contacts.size()), steer_c(P.wheels.size()),
        steer_s(P.wheels.size()) {}
  std::vector<BodyL<V>> bodies;
  std::vector<PointL<V>> pts;
  std::vector<ContactL<V>> con;
  std::vector<Held<V>> steer_c, steer_s;  // cos, sin of each wheel's steering angle
  alignas(32) V drive_power{};
  int sweeps = 0;
};

template <class V> GROUNDSIM_INLINE_BODY V dot3(const V* a, const V* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
template <class V> GROUNDSIM_INLINE_BODY void cross3(const V* a, const V* b, V* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
template <class V> GROUNDSIM_INLINE_BODY void mat3vec(const V* M, const V* x, V* out) {
  for (int i = 0; i < 3; ++i) out[i] = M[3 * i] * x[0] + M[3 * i + 1] * x[1] + M[3 * i + 2] * x[2];
}
// Rotation matrix (row-major) of the unit quaternion (x, y, z, w): Eigen's formula.
template <class V> GROUNDSIM_INLINE_BODY void quatToMat(V x, V y, V z, V w, V* R) {
  const V tx = 2.0 * x, ty = 2.0 * y, tz = 2.0 * z;
  const V twx = tx * w, twy = ty * w, twz = tz * w, txx = tx * x, txy = ty * x, txz = tz * x;
  const V tyy = ty * y, tyz = tz * y, tzz = tz * z;
  R[0] = 1.0 - (tyy + tzz); R[1] = txy - twz; R[2] = txz + twy;
  R[3] = txy + twz; R[4] = 1.0 - (txx + tzz); R[5] = tyz - twx;
  R[6] = txz - twy; R[7] = tyz + twx; R[8] = 1.0 - (txx + tyy);
}
GROUNDSIM_INLINE_BODY bool isDiagonal(const double* B) {
  return B[1] == 0.0 && B[2] == 0.0 && B[3] == 0.0 && B[5] == 0.0 && B[6] == 0.0 && B[7] == 0.0;
}
// Column k of quatToMat's matrix: a symmetric body's world axis.
template <class V> GROUNDSIM_INLINE_BODY void quatAxis(V x, V y, V z, V w, int k, V* c) {
  const V tx = 2.0 * x, ty = 2.0 * y, tz = 2.0 * z;
  if (k == 0) {
    c[0] = 1.0 - (ty * y + tz * z); c[1] = ty * x + tz * w; c[2] = tz * x - ty * w;
  } else if (k == 1) {
    c[0] = ty * x - tz * w; c[1] = 1.0 - (tx * x + tz * z); c[2] = tz * y + tx * w;
  } else {
    c[0] = tz * x + ty * w; c[1] = tz * y - tx * w; c[2] = 1.0 - (tx * x + ty * y);
  }
}
// out = Iw x: iso x + along (c.x) c for a body symmetric about c, else the matrix.
template <class V>
GROUNDSIM_INLINE_BODY void invInertia(const FastCarPlan::BodyC& bc, const BodyL<V>& B, const V* x, V* out) {
  if (bc.axis >= 0) {
    const V s = bc.along * dot3(B.c, x);
    for (int d = 0; d < 3; ++d) out[d] = bc.iso * x[d] + s * B.c[d];
    return;
  }
  mat3vec(B.Iw, x, out);
}
// R B R^T for row-major 3x3 R and a constant B. A diagonal B (the
// principal axes of every body the car builders make) skips the zero
// terms, which add nothing, and takes the symmetric half.
template <class V> GROUNDSIM_INLINE_BODY void rotateInertia(const V* R, const double* B, bool diagonal, V* out) {
  if (diagonal) {
    V M[9];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) M[3 * i + k] = R[3 * i + k] * B[4 * k];
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        out[3 * i + j] = M[3 * i] * R[3 * j] + M[3 * i + 1] * R[3 * j + 1] + M[3 * i + 2] * R[3 * j + 2];
        out[3 * j + i] = out[3 * i + j];
      }
    return;
  }
  V M[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M[3 * i + j] = R[3 * i] * B[j] + R[3 * i + 1] * B[3 + j] + R[3 * i + 2] * B[6 + j];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = M[3 * i] * R[3 * j] + M[3 * i + 1] * R[3 * j + 1] + M[3 * i + 2] * R[3 * j + 2];
}
// The same, B's shape looked up (for callers without a classified plan: ring_car.cpp).
template <class V> GROUNDSIM_INLINE_BODY void rotateInertia(const V* R, const double* B, V* out) {
  rotateInertia(R, B, isDiagonal(B), out);
}
// omega = R B R^T L, as R (B (R^T L)).
template <class V> GROUNDSIM_INLINE_BODY void spinOf(const V* R, const double* B, bool diagonal, const V* L, V* w) {
  V b[3], c[3];
  for (int j = 0; j < 3; ++j) b[j] = R[j] * L[0] + R[3 + j] * L[1] + R[6 + j] * L[2];
  if (diagonal)
    for (int i = 0; i < 3; ++i) c[i] = B[4 * i] * b[i];
  else
    for (int i = 0; i < 3; ++i) c[i] = B[3 * i] * b[0] + B[3 * i + 1] * b[1] + B[3 * i + 2] * b[2];
  mat3vec(R, c, w);
}
template <class V> GROUNDSIM_INLINE_BODY void spinOf(const V* R, const double* B, const V* L, V* w) {
  spinOf(R, B, isDiagonal(B), L, w);
}

// q (x y z w) turned by the rotation vector (wx, wy, wz) * h and
// normalised: math.hpp's integrateRotation. Small angles (all a car's
// wheels below ~12 rad/s per ms of step) by the series of cos(a/2) and
// sin(a/2)/a to a^6, whose next terms (a^8 / 1e7) are below round-off
// there; larger ones by sin and cos, lane by lane.
// normalise = false: the half-step orientation, used only for its rotation
// matrix, off unit length by round-off only (a product of unit quaternions).
template <class V>
GROUNDSIM_INLINE_BODY void turn(const V* q, const V* omega, double h, V* out, bool normalise = true) {
  using L = Lane<V>;
  const V wx = omega[0] * h, wy = omega[1] * h, wz = omega[2] * h;
  const V a2 = wx * wx + wy * wy + wz * wz;
  // Horner, multiplying by the coefficients: a division costs several multiplies
  V c, s;
  pointwise::halfAngleSeries(a2, c, s);
  if (L::any(a2 >= pointwise::kRotationSeries)) {
    for (int l = 0; l < L::n; ++l) {
      const double a2l = L::get(a2, l);
      if (a2l < pointwise::kRotationSeries) continue;
      const double angle = std::sqrt(a2l), ha = 0.5 * angle;
      L::at(c, l) = std::cos(ha);
      L::at(s, l) = std::sin(ha) / angle;
    }
  }
  const V dw = c, dx = s * wx, dy = s * wy, dz = s * wz;
  const V bx = q[0], by = q[1], bz = q[2], bw = q[3];
  const V rw = dw * bw - dx * bx - dy * by - dz * bz;
  const V rx = dw * bx + dx * bw + dy * bz - dz * by;
  const V ry = dw * by + dy * bw + dz * bx - dx * bz;
  const V rz = dw * bz + dz * bw + dx * by - dy * bx;
  if (!normalise) {
    out[0] = rx, out[1] = ry, out[2] = rz, out[3] = rw;
    return;
  }
  const V inv = 1.0 / L::sqrt(rx * rx + ry * ry + rz * rz + rw * rw);
  out[0] = rx * inv;
  out[1] = ry * inv;
  out[2] = rz * inv;
  out[3] = rw * inv;
}

}  // namespace groundsim::fastcar
