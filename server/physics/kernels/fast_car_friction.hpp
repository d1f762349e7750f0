// The specialised car step's stick-slip friction and brakes
// (velocity_constraints.cpp, lane-masked), in phases; part of
// fast_car_kernel.hpp, inlined as it is.
#pragma once

#include "physics/kernels/fast_car_lanes.hpp"

namespace groundsim::fastcar {

// frictionAndBrakes' phases, in their order.

// The bodies' velocities after h under the forces so far (friction's start).
template <class V>
GROUNDSIM_INLINE_BODY void predictVelocities(const FastCarPlan& P, const V* Y, double h, Scratch<V>& S) {
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
}

// Each touching slot's 2x2 tangential effective mass and its inverse, and
// the impulses' scale for the convergence test (with the brakes').
template <class V>
GROUNDSIM_INLINE_BODY V contactMasses(const FastCarPlan& P, const V* brake, double h, const V t1[3], const V t2[3],
                                      Scratch<V>& S) {
  using L = Lane<V>;
  V scale = L::all(0.0);
  for (size_t k = 0; k < S.con.size(); ++k) {
    ContactL<V>& c = S.con[k];
    if (static_cast<int>(k) < P.point_contacts && !c.any_in) continue;  // never touched this step
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
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const V b = brake[w];
    scale += (b < 0.0 ? L::all(0.0) : b) * h;
  }
  return scale;
}

// What a brake sweep needs of each axle's inertia: the same every sweep.
template <class V>
GROUNDSIM_INLINE_BODY void axleInertias(const FastCarPlan& P, Scratch<V>& S) {
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const FastCarPlan::WheelC& wc = P.wheels[w];
    if (wc.carrier < 0) continue;
    ContactL<V>& c = S.con[P.point_contacts + w];
    invInertia(P.bodies[wc.body], S.bodies[wc.body], c.a, c.ia);
    invInertia(P.bodies[wc.carrier], S.bodies[wc.carrier], c.a, c.ic);
    c.bden = dot3(c.a, c.ia) + dot3(c.a, c.ic);
  }
}

// One sweep's brakes in the `active` lanes: each braked wheel's impulse
// about its axle, clamped to its torque times h, against its carrier.
template <class V>
GROUNDSIM_INLINE_BODY void brakeSweep(const FastCarPlan& P, const V* brake, double h, typename Lane<V>::M active,
                                      Scratch<V>& S, V& change, V& total) {
  using M = typename Lane<V>::M;
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const FastCarPlan::WheelC& wc = P.wheels[w];
    if (wc.carrier < 0) continue;
    ContactL<V>& c = S.con[P.point_contacts + w];
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

// One sweep's contacts in slot order (the general path's), in the
// `active` lanes: each contact's tangential impulse inside its friction disc.
template <class V>
GROUNDSIM_INLINE_BODY void contactSweep(const FastCarPlan& P, double h, const V t1[3], const V t2[3],
                                        typename Lane<V>::M active, Scratch<V>& S, V& change, V& total) {
  using L = Lane<V>;
  using M = typename L::M;
  for (size_t k = 0; k < S.con.size(); ++k) {
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
}

// The brake and friction impulses over the step become forces and torques.
template <class V>
GROUNDSIM_INLINE_BODY void impulsesAsForces(const FastCarPlan& P, double h, bool any_brake, const V t1[3],
                                            const V t2[3], Scratch<V>& S) {
  if (any_brake) {
    for (size_t w = 0; w < P.wheels.size(); ++w) {
      const FastCarPlan::WheelC& wc = P.wheels[w];
      if (wc.carrier < 0) continue;
      const ContactL<V>& c = S.con[P.point_contacts + w];
      BodyL<V>& B = S.bodies[wc.body];
      BodyL<V>& C = S.bodies[wc.carrier];
      const V tb = c.bi / h;
      for (int k = 0; k < 3; ++k) {
        B.T[k] += tb * c.a[k];
        C.T[k] -= tb * c.a[k];
      }
    }
  }
  for (size_t k = 0; k < S.con.size(); ++k) {
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

// Stick-slip friction and brakes: velocity_constraints.cpp, lane-masked.
// Contacts in slot order (the general path's order), brakes first in each
// sweep; a lane whose sweeps have converged keeps its impulses.
template <class V>
GROUNDSIM_INLINE_BODY void frictionAndBrakes(const FastCarPlan& P, const V* Y, const V* brake, double h,
                                             Scratch<V>& S) {
  using L = Lane<V>;
  using M = typename L::M;
  M touching = S.con[0].in;
  for (size_t k = 1; k < S.con.size(); ++k) touching = touching | S.con[k].in;
  M braking = brake[0] > 0.0;
  for (size_t w = 1; w < P.wheels.size(); ++w) braking = braking | (brake[w] > 0.0);
  S.sweeps = 0;
  for (ContactL<V>& c : S.con) c.bi = c.j0 = c.j1 = L::all(0.0);
  if (!L::any(touching) && !L::any(braking)) return;  // nothing to solve in any lane
  predictVelocities(P, Y, h, S);
  const V t1[3] = {L::all(P.t1[0]), L::all(P.t1[1]), L::all(P.t1[2])};
  const V t2[3] = {L::all(P.t2[0]), L::all(P.t2[1]), L::all(P.t2[2])};
  const V scale = contactMasses(P, brake, h, t1, t2, S);
  M active = touching | braking;
  const bool any_brake = L::any(braking);
  if (any_brake) axleInertias(P, S);
  for (int iter = 0; iter < P.friction_iterations; ++iter) {
    V change = L::all(0.0), total = L::all(0.0);
    if (any_brake) brakeSweep(P, brake, h, active, S, change, total);
    contactSweep(P, h, t1, t2, active, S, change, total);
    S.sweeps = iter + 1;
    // converged: what is left cannot add up to creep
    active = L::andNot(active, pointwise::converged(change, total, scale));
    if (!L::any(active)) break;
  }
  impulsesAsForces(P, h, any_brake, t1, t2, S);
}

}  // namespace groundsim::fastcar
