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
#include "physics/kernels/fast_car_lanes.hpp"
#include "physics/kernels/rigid_friction.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim::fastcar {

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

// 4.2's phases, in their order.

// One spring-dashpot between two points (springs.cpp's applyOne): its
// force added to a's, taken from b's. Pt: any point with position p,
// velocity u and force f (the fast car's lanes, the ring car's plain points).
template <class V, class Spring, class Pt>
GROUNDSIM_INLINE_BODY void springBetween(const Spring& sp, Pt& A, Pt& Bp) {
  using L = Lane<V>;
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

// The springs between points, on zeroed point forces.
template <class V>
GROUNDSIM_INLINE_BODY void springForces(const FastCarPlan& P, Scratch<V>& S) {
  using L = Lane<V>;
  for (PointL<V>& pt : S.pts) pt.f[0] = pt.f[1] = pt.f[2] = L::all(0.0);
  for (const FastCarPlan::SpringC& sp : P.springs) springBetween<V>(sp, S.pts[sp.a], S.pts[sp.b]);
}

// The contact slots of body points (a car's axle points touch only when it
// rolls over): where they are and how fast they move.
template <class V>
GROUNDSIM_INLINE_BODY void pointContacts(const FastCarPlan& P, const V* Y, Scratch<V>& S) {
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
}

// Each wheel's deepest circle point on the plane, in closed form.
template <class V>
GROUNDSIM_INLINE_BODY void wheelContacts(const FastCarPlan& P, const V* Y, Scratch<V>& S) {
  using L = Lane<V>;
  const double nx = P.n[0], ny = P.n[1], nz = P.n[2];
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
}

// Depth and normal force (report eq. 10 with damping) for every slot.
template <class V>
GROUNDSIM_INLINE_BODY void normalForces(const FastCarPlan& P, const double cn[3], Scratch<V>& S) {
  using L = Lane<V>;
  const double nx = P.n[0], ny = P.n[1], nz = P.n[2];
  for (ContactL<V>& c : S.con) {
    const V H = nx * c.p[0] + ny * c.p[1] + nz * c.p[2] - P.offset;
    c.in = H < 0.0;
    c.any_in = L::any(c.in);
    c.depth = -H * P.inv_gn;
    const V rate = -(c.u[0] * cn[0] + c.u[1] * cn[1] + c.u[2] * cn[2]);
    const V N = pointwise::penaltyNormal(P.stiffness, c.depth, P.damping, rate, P.hunt_crossley);
    c.N = c.in ? N : L::all(0.0);
  }
}

// Gravity, then the sums over each body's points, then the contacts' normal forces.
template <class V>
GROUNDSIM_INLINE_BODY void bodySums(const FastCarPlan& P, const double cn[3], Scratch<V>& S) {
  using L = Lane<V>;
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
}

// Drive torque about each axle, its reaction on the carrier.
template <class V>
GROUNDSIM_INLINE_BODY void driveTorques(const FastCarPlan& P, const V* drive, Scratch<V>& S) {
  using L = Lane<V>;
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

// 4.2: springs, circle contacts, gravity and point sums, drive.
template <class V>
GROUNDSIM_INLINE_BODY void forces(const FastCarPlan& P, const V* Y, const V* drive, Scratch<V>& S) {
  const double cn[3] = {P.n[0] / P.gn, P.n[1] / P.gn, P.n[2] / P.gn};
  springForces(P, S);
  pointContacts(P, Y, S);
  wheelContacts(P, Y, S);
  normalForces(P, cn, S);
  bodySums(P, cn, S);
  driveTorques(P, drive, S);
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

// The car's contact slots as the shared friction solve reads them
// (rigid_friction.hpp): fixed slots (body points, then one per wheel),
// lane-masked, one mu; each wheel's slot also holds its axle's brake.
template <class V> struct SlotSet {
  const FastCarPlan& P;
  Scratch<V>& S;
  size_t slots() const { return S.con.size(); }
  bool solves(size_t k) const { return S.con[k].any_in; }
  typename Lane<V>::M in(size_t k) const { return S.con[k].in; }
  ContactL<V>& at(size_t k) { return S.con[k]; }
  int body(size_t k) const { return P.contacts[k].body; }
  double mu(size_t) const { return P.mu; }
  typename Lane<V>::M touching() const {
    typename Lane<V>::M t = S.con[0].in;
    for (size_t k = 1; k < S.con.size(); ++k) t = t | S.con[k].in;
    return t;
  }
  size_t axles() const { return P.wheels.size(); }
  int axleBody(size_t w) const { return P.wheels[w].body; }
  int axleCarrier(size_t w) const { return P.wheels[w].carrier; }
  ContactL<V>& axle(size_t w) { return S.con[P.point_contacts + w]; }
};

// Stick-slip friction and brakes: the shared rigid solve over the car's slots.
template <class V>
GROUNDSIM_INLINE_BODY void frictionAndBrakes(const FastCarPlan& P, const V* Y, const V* brake, double h,
                                             Scratch<V>& S) {
  const rigid::FrictionInput<V> in{P.bodies.data(), S.bodies.data(), S.bodies.size(), Y, brake, P.t1, P.t2, h,
                                   P.friction_iterations};
  SlotSet<V> set{P, S};
  S.sweeps = rigid::frictionAndBrakes(in, set);
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
