// The specialised car step (fast_car.hpp) as a template over the lane type
// V: `double` (one car) or `v4d` (four cars, one per SIMD lane). Lanes never
// interact; where a car takes a branch (a wheel in the air, a sliding
// contact, a friction solve that has converged) both sides are computed and
// selected per lane, so every lane gets exactly the arithmetic the car
// would get alone. Included by fast_car.cpp and batch_step.cpp only; every
// function is inlined into that file's wide (AVX2) and generic builds.
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

// 4.1: rotations, world inertia, spin, and the points springs hang on.
template <class V>
GROUNDSIM_INLINE_BODY void kinematics(const FastCarPlan& P, const V* Y, const V* steer, Scratch<V>& S) {
  using L = Lane<V>;
  for (size_t i = 0; i < P.bodies.size(); ++i) {
    BodyL<V>& B = S.bodies[i];
    const V* y = Y + 13 * i;
    const FastCarPlan::BodyC& bc = P.bodies[i];
    const V inq = 1.0 / L::sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]);
    quatToMat(y[3] * inq, y[4] * inq, y[5] * inq, y[6] * inq, B.R);
    if (bc.axis >= 0)
      for (int d = 0; d < 3; ++d) B.c[d] = B.R[3 * d + bc.axis];
    else
      rotateInertia(B.R, bc.Ib, bc.diagonal, B.Iw);
    invInertia(bc, B, y + 10, B.w);
  }
  // cos and sin of each wheel's steering angle, once per wheel and lane (not
  // per point), and not at all for a wheel no lane steers: the points then
  // take vector arithmetic, not lane-by-lane stores into a vector
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    S.steer_c[w].v = L::all(1.0);
    S.steer_s[w].v = L::all(0.0);
    if (!L::any(steer[w] != 0.0)) continue;
    for (int ln = 0; ln < L::n; ++ln) {
      const double al = L::get(steer[w], ln);
      if (al == 0.0) continue;
      L::at(S.steer_c[w].v, ln) = std::cos(al);
      L::at(S.steer_s[w].v, ln) = std::sin(al);
    }
  }
  for (size_t k = 0; k < P.pts.size(); ++k) {
    const FastCarPlan::PointC& pc = P.pts[k];
    PointL<V>& pt = S.pts[k];
    const BodyL<V>& B = S.bodies[pc.body];
    const V* y = Y + 13 * pc.body;
    V l[3] = {L::all(pc.lx), L::all(pc.ly), L::all(pc.lz)};
    if (pc.steer_wheel >= 0) {
      const V c = S.steer_c[pc.steer_wheel].v, s = S.steer_s[pc.steer_wheel].v;
      l[0] = pc.pivx + c * pc.dx - s * pc.dy;
      l[1] = pc.pivy + s * pc.dx + c * pc.dy;
    }
    mat3vec(B.R, l, pt.r);
    for (int d = 0; d < 3; ++d) pt.p[d] = y[d] + pt.r[d];
    V wr[3];
    cross3(B.w, pt.r, wr);
    for (int d = 0; d < 3; ++d) pt.u[d] = y[7 + d] + wr[d];
  }
}

// 4.2: springs, circle contacts, gravity and point sums, drive.
template <class V>
GROUNDSIM_INLINE_BODY void forces(const FastCarPlan& P, const V* Y, const V* drive, Scratch<V>& S) {
  using L = Lane<V>;
  for (PointL<V>& pt : S.pts) pt.f[0] = pt.f[1] = pt.f[2] = L::all(0.0);
  for (const FastCarPlan::SpringC& sp : P.springs) {
    PointL<V>& A = S.pts[sp.a];
    PointL<V>& Bp = S.pts[sp.b];
    V d[3], e[3], g[3];
    for (int k = 0; k < 3; ++k) {
      d[k] = Bp.p[k] - A.p[k];
      e[k] = Bp.u[k] - A.u[k];
    }
    if (sp.isotropic) {
      for (int k = 0; k < 3; ++k) g[k] = sp.k * d[k] + sp.c * e[k];
    } else {
      const V len2 = dot3(d, d);
      const V inv = 1.0 / L::sqrt(len2 + 1e-300);
      const V t = pointwise::springTension(len2, inv, dot3(d, e), sp.k, sp.c, sp.rest);
      for (int k = 0; k < 3; ++k) g[k] = t * d[k];
    }
    for (int k = 0; k < 3; ++k) {
      A.f[k] += g[k];
      Bp.f[k] -= g[k];
    }
  }
  const double nx = P.n[0], ny = P.n[1], nz = P.n[2];
  const double cn[3] = {nx / P.gn, ny / P.gn, nz / P.gn};
  // body points below the plane (a car's axle points only when it rolls over)
  for (int slot = 0; slot < P.point_contacts; ++slot) {
    ContactL<V>& c = S.con[slot];
    const PointL<V>& pt = S.pts[P.contacts[slot].pt];
    const V* y = Y + 13 * P.contacts[slot].body;
    for (int k = 0; k < 3; ++k) {
      c.p[k] = pt.p[k];
      c.rr[k] = pt.p[k] - y[k];
      c.u[k] = pt.u[k];
    }
  }
  // each wheel's deepest circle point on the plane, in closed form
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const FastCarPlan::WheelC& wc = P.wheels[w];
    ContactL<V>& c = S.con[P.point_contacts + w];
    const BodyL<V>& B = S.bodies[wc.body];
    const V* y = Y + 13 * wc.body;
    const V axis[3] = {L::all(wc.ax), L::all(wc.ay), L::all(wc.az)};
    mat3vec(B.R, axis, c.a);
    const V na = nx * c.a[0] + ny * c.a[1] + nz * c.a[2];
    V d[3] = {-(nx - na * c.a[0]), -(ny - na * c.a[1]), -(nz - na * c.a[2])};
    const V dn = L::sqrt(dot3(d, d));
    const auto flat = dn < 1e-12;
    const V inv_dn = 1.0 / dn;
    for (int k = 0; k < 3; ++k) d[k] = d[k] * inv_dn;
    if (L::any(flat)) {  // lying flat: any rim point
      for (int ln = 0; ln < L::n; ++ln) {
        if (!(L::get(dn, ln) < 1e-12)) continue;
        const Vec3 o = Vec3(L::get(c.a[0], ln), L::get(c.a[1], ln), L::get(c.a[2], ln)).unitOrthogonal();
        for (int k = 0; k < 3; ++k) L::at(d[k], ln) = o[k];
      }
    }
    for (int k = 0; k < 3; ++k) {
      c.p[k] = y[k] + wc.radius * d[k];
      c.rr[k] = c.p[k] - y[k];
    }
    V wr[3];
    cross3(B.w, c.rr, wr);
    for (int k = 0; k < 3; ++k) c.u[k] = y[7 + k] + wr[k];
  }
  // depth and normal force (report eq. 10 with damping) for every slot
  for (ContactL<V>& c : S.con) {
    const V H = nx * c.p[0] + ny * c.p[1] + nz * c.p[2] - P.offset;
    c.in = H < 0.0;
    c.any_in = L::any(c.in);
    c.depth = -H * P.inv_gn;
    const V rate = -(c.u[0] * cn[0] + c.u[1] * cn[1] + c.u[2] * cn[2]);
    const V N = pointwise::penaltyNormal(P.stiffness, c.depth, P.damping, rate, P.hunt_crossley);
    c.N = c.in ? N : L::all(0.0);
  }
  // gravity, then the sums over each body's points, then the contacts
  for (size_t i = 0; i < P.bodies.size(); ++i) {
    const FastCarPlan::BodyC& bc = P.bodies[i];
    BodyL<V>& B = S.bodies[i];
    V F[3] = {L::all(0.0), L::all(0.0), L::all(0.0)}, T[3] = {F[0], F[1], F[2]};
    for (int k = bc.first_point; k < bc.end_point; ++k) {
      const PointL<V>& pt = S.pts[k];
      V rf[3];
      cross3(pt.r, pt.f, rf);
      for (int d = 0; d < 3; ++d) {
        F[d] += pt.f[d];
        T[d] += rf[d];
      }
    }
    for (int d = 0; d < 3; ++d) {
      B.F[d] = bc.mass * P.gravity[d] + F[d];
      B.T[d] = T[d];
    }
  }
  for (size_t slot = 0; slot < S.con.size(); ++slot) {
    ContactL<V>& c = S.con[slot];
    if (slot < static_cast<size_t>(P.point_contacts) && !c.any_in) continue;  // adds zero
    BodyL<V>& B = S.bodies[P.contacts[slot].body];
    const V f[3] = {cn[0] * c.N, cn[1] * c.N, cn[2] * c.N};
    V rf[3];
    cross3(c.rr, f, rf);
    for (int d = 0; d < 3; ++d) {
      B.F[d] += f[d];
      B.T[d] += rf[d];
    }
  }
  // drive torque about the axle, reaction on the carrier
  S.drive_power = L::all(0.0);
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const FastCarPlan::WheelC& wc = P.wheels[w];
    const V Tq = drive[w];
    const ContactL<V>& c = S.con[P.point_contacts + w];
    BodyL<V>& B = S.bodies[wc.body];
    for (int d = 0; d < 3; ++d) B.T[d] += Tq * c.a[d];
    if (wc.carrier < 0) {
      S.drive_power += Tq * dot3(c.a, B.w);
      continue;
    }
    BodyL<V>& C = S.bodies[wc.carrier];
    for (int d = 0; d < 3; ++d) C.T[d] -= Tq * c.a[d];
    const V rel[3] = {B.w[0] - C.w[0], B.w[1] - C.w[1], B.w[2] - C.w[2]};
    S.drive_power += Tq * dot3(c.a, rel);
  }
}

// Stick-slip friction and brakes: velocity_constraints.cpp, lane-masked.
// Contacts in slot order (the general path's order), brakes first in each
// sweep; a lane whose sweeps have converged keeps its impulses.
template <class V>
GROUNDSIM_INLINE_BODY void frictionAndBrakes(const FastCarPlan& P, const V* Y, const V* brake, double h,
                                             Scratch<V>& S) {
  using L = Lane<V>;
  using M = typename L::M;
  const size_t nw = P.wheels.size(), ns = S.con.size();
  const int pc = P.point_contacts;
  M touching = S.con[0].in;
  for (size_t k = 1; k < ns; ++k) touching = touching | S.con[k].in;
  M braking = brake[0] > 0.0;
  for (size_t w = 1; w < nw; ++w) braking = braking | (brake[w] > 0.0);
  S.sweeps = 0;
  for (ContactL<V>& c : S.con) c.bi = c.j0 = c.j1 = L::all(0.0);
  if (!L::any(touching) && !L::any(braking)) return;  // nothing to solve in any lane
  for (size_t i = 0; i < P.bodies.size(); ++i) {
    BodyL<V>& B = S.bodies[i];
    const V* y = Y + 13 * i;
    const double inv_m = P.bodies[i].inv_mass;
    V Lh[3];
    for (int d = 0; d < 3; ++d) {
      B.vp[d] = y[7 + d] + h * B.F[d] * inv_m;
      Lh[d] = y[10 + d] + h * B.T[d];
    }
    invInertia(P.bodies[i], B, Lh, B.wp);
  }
  const V t1[3] = {L::all(P.t1[0]), L::all(P.t1[1]), L::all(P.t1[2])};
  const V t2[3] = {L::all(P.t2[0]), L::all(P.t2[1]), L::all(P.t2[2])};
  V scale = L::all(0.0);
  for (size_t k = 0; k < ns; ++k) {
    ContactL<V>& c = S.con[k];
    if (static_cast<int>(k) < pc && !c.any_in) continue;  // never touched this step
    const int bi = P.contacts[k].body;
    const BodyL<V>& B = S.bodies[bi];
    const double inv_m = P.bodies[bi].inv_mass;
    cross3(c.rr, t1, c.a1);
    cross3(c.rr, t2, c.a2);
    invInertia(P.bodies[bi], B, c.a1, c.b1);
    invInertia(P.bodies[bi], B, c.a2, c.b2);
    c.k01 = dot3(c.a1, c.b2);
    c.k00 = inv_m + dot3(c.a1, c.b1);
    c.k11 = inv_m + dot3(c.a2, c.b2);
    const V invdet = 1.0 / (c.k00 * c.k11 - c.k01 * c.k01);
    c.i00 = c.k11 * invdet;
    c.i10 = -c.k01 * invdet;
    c.i01 = -c.k01 * invdet;
    c.i11 = c.k00 * invdet;
    scale += P.mu * c.N * h;
  }
  for (size_t w = 0; w < nw; ++w) {
    const V b = brake[w];
    scale += (b < 0.0 ? L::all(0.0) : b) * h;
  }
  M active = touching | braking;
  const bool any_brake = L::any(braking);
  if (any_brake)  // what a brake sweep needs of the axle's inertia: the same every sweep
    for (size_t w = 0; w < nw; ++w) {
      const FastCarPlan::WheelC& wc = P.wheels[w];
      if (wc.carrier < 0) continue;
      ContactL<V>& c = S.con[pc + w];
      invInertia(P.bodies[wc.body], S.bodies[wc.body], c.a, c.ia);
      invInertia(P.bodies[wc.carrier], S.bodies[wc.carrier], c.a, c.ic);
      c.bden = dot3(c.a, c.ia) + dot3(c.a, c.ic);
    }
  for (int iter = 0; iter < P.friction_iterations; ++iter) {
    V change = L::all(0.0), total = L::all(0.0);
    if (any_brake) {
      for (size_t w = 0; w < nw; ++w) {
        const FastCarPlan::WheelC& wc = P.wheels[w];
        if (wc.carrier < 0) continue;
        ContactL<V>& c = S.con[pc + w];
        BodyL<V>& B = S.bodies[wc.body];
        BodyL<V>& C = S.bodies[wc.carrier];
        const V Bh = brake[w] * h;
        const V* ia = c.ia;
        const V* ic = c.ic;
        const V rel[3] = {B.wp[0] - C.wp[0], B.wp[1] - C.wp[1], B.wp[2] - C.wp[2]};
        const V spin = dot3(c.a, rel);
        V acc = c.bi - spin / c.bden;
        acc = acc < -Bh ? -Bh : (Bh < acc ? Bh : acc);
        const M on = active & (brake[w] > 0.0);
        acc = on ? acc : c.bi;
        const V d = acc - c.bi;
        c.bi = acc;
        change += d < 0.0 ? -d : d;
        total += acc < 0.0 ? -acc : acc;
        for (int k = 0; k < 3; ++k) {
          B.wp[k] += d * ia[k];
          C.wp[k] -= d * ic[k];
        }
      }
    }
    for (size_t k = 0; k < ns; ++k) {
      ContactL<V>& c = S.con[k];
      // a lane not `on` computes a zero change: it does not touch (impulse 0),
      // or it has converged and its change and total are no longer read
      if (!c.any_in) continue;
      const M on = active & c.in;
      const int bi = P.contacts[k].body;
      BodyL<V>& B = S.bodies[bi];
      const V ut0 = dot3(t1, B.vp) + dot3(B.wp, c.a1);
      const V ut1 = dot3(t2, B.vp) + dot3(B.wp, c.a2);
      V acc0 = c.j0 - (c.i00 * ut0 + c.i01 * ut1);
      V acc1 = c.j1 - (c.i10 * ut0 + c.i11 * ut1);
      const V limit = P.mu * c.N * h;
      const V an = L::sqrt(acc0 * acc0 + acc1 * acc1);
      // sliding: mu N opposite the slip this contact would have without its own friction
      const V free0 = ut0 - (c.k00 * c.j0 + c.k01 * c.j1);
      const V free1 = ut1 - (c.k01 * c.j0 + c.k11 * c.j1);
      const V fn = L::sqrt(free0 * free0 + free1 * free1);
      const auto slide = an > limit;
      if (L::any(slide)) {
        const V sl = -limit / fn, sc = limit / an;
        const auto big = fn > 1e-12;
        const V s0 = big ? sl * free0 : acc0 * sc, s1 = big ? sl * free1 : acc1 * sc;
        acc0 = slide ? s0 : acc0;
        acc1 = slide ? s1 : acc1;
      }
      acc0 = on ? acc0 : c.j0;
      acc1 = on ? acc1 : c.j1;
      const V d0 = acc0 - c.j0, d1 = acc1 - c.j1;
      c.j0 = acc0;
      c.j1 = acc1;
      change += (d0 < 0.0 ? -d0 : d0) + (d1 < 0.0 ? -d1 : d1);
      total += (acc0 < 0.0 ? -acc0 : acc0) + (acc1 < 0.0 ? -acc1 : acc1);
      const double inv_m = P.bodies[bi].inv_mass;
      for (int q = 0; q < 3; ++q) {
        B.vp[q] += (d0 * t1[q] + d1 * t2[q]) * inv_m;
        B.wp[q] += d0 * c.b1[q] + d1 * c.b2[q];
      }
    }
    S.sweeps = iter + 1;
    // converged: what is left cannot add up to creep
    active = L::andNot(active, pointwise::converged(change, total, scale));
    if (!L::any(active)) break;
  }
  // impulses over the step become forces
  if (any_brake) {
    for (size_t w = 0; w < nw; ++w) {
      const FastCarPlan::WheelC& wc = P.wheels[w];
      if (wc.carrier < 0) continue;
      const ContactL<V>& c = S.con[pc + w];
      BodyL<V>& B = S.bodies[wc.body];
      BodyL<V>& C = S.bodies[wc.carrier];
      const V tb = c.bi / h;
      for (int k = 0; k < 3; ++k) {
        B.T[k] += tb * c.a[k];
        C.T[k] -= tb * c.a[k];
      }
    }
  }
  for (size_t k = 0; k < ns; ++k) {
    const ContactL<V>& c = S.con[k];
    if (!c.any_in) continue;  // no impulse in any lane
    BodyL<V>& B = S.bodies[P.contacts[k].body];
    V f[3], rf[3];
    for (int q = 0; q < 3; ++q) f[q] = (c.j0 * t1[q] + c.j1 * t2[q]) * (1.0 / h);
    cross3(c.rr, f, rf);
    for (int q = 0; q < 3; ++q) {
      B.F[q] += f[q];
      B.T[q] += rf[q];
    }
  }
}

// Semi-implicit Euler (semi_implicit_euler.cpp): momenta, positions, the
// midpoint rotation with one pass.
template <class V>
GROUNDSIM_INLINE_BODY void integrate(const FastCarPlan& P, V* Y, double h, Scratch<V>& S) {
  for (size_t i = 0; i < P.bodies.size(); ++i) {
    const FastCarPlan::BodyC& bc = P.bodies[i];
    BodyL<V>& B = S.bodies[i];
    V* y = Y + 13 * i;
    for (int d = 0; d < 3; ++d) {
      y[7 + d] += h * B.F[d] * bc.inv_mass;
      y[10 + d] += h * B.T[d];
      y[d] += h * y[7 + d];
    }
    V w0[3], w[3], qm[4];
    const V q0[4] = {y[3], y[4], y[5], y[6]};
    invInertia(bc, B, y + 10, w0);
    turn(q0, w0, 0.5 * h, qm, false);
    if (bc.axis >= 0) {  // the midpoint's inertia needs only its axis
      V cm[3];
      quatAxis(qm[0], qm[1], qm[2], qm[3], bc.axis, cm);
      const V s = bc.along * dot3(cm, y + 10);
      for (int d = 0; d < 3; ++d) w[d] = bc.iso * y[10 + d] + s * cm[d];
    } else {
      V Rm[9];
      quatToMat(qm[0], qm[1], qm[2], qm[3], Rm);
      spinOf(Rm, bc.Ib, bc.diagonal, y + 10, w);
    }
    turn(q0, w, h, y + 3);
  }
}

// One integrator step h: evaluation, then the update. Returns the drive power.
template <class V>
GROUNDSIM_INLINE_BODY void advance(const FastCarPlan& P, V* Y, const V* drive, const V* brake, const V* steer,
                                   double h, Scratch<V>& S, V* drive_work) {
  kinematics(P, Y, steer, S);
  forces(P, Y, drive, S);
  frictionAndBrakes(P, Y, brake, h, S);
  *drive_work += h * S.drive_power;
  integrate(P, Y, h, S);
}

}  // namespace groundsim::fastcar
