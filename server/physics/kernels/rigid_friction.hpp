// The rigid paths' stick-slip friction and brakes (velocity_constraints.cpp
// is the reference it matches up to round-off), written once as a template
// over the lane type V (`double`: one car; `v4d`: four cars) and over the
// path's contact set. Both rigid kernels take it: the circle-wheel car
// (fast_car_kernel.hpp: fixed slots, lane-masked, one mu) and the report's
// ring car (ring_car.cpp: a compacted list, a mu per contact). Inlined into
// each caller's wide and generic builds.
//
// A contact set `Set` gives, for slot k in [0, set.slots()):
//   set.solves(k)  some lane touches: the slot is solved (else it adds zero)
//   set.in(k)      the lanes that touch (a mask; `true` for one car)
//   set.at(k)      the slot: rr[3] (lever arm), N, and the solve's fields
//                  a1 a2 b1 b2 k00 k01 k11 i00 i01 i10 i11 j0 j1
//   set.body(k)    the body it acts on
//   set.mu(k)      its friction coefficient
// and for each braked axle w in [0, set.axles()):
//   set.axleBody(w), set.axleCarrier(w) (-1: none, never braked)
//   set.axle(w)    the axle's fields: a[3] (world axis), ia ic bden bi
#pragma once

#include "physics/base/pointwise.hpp"
#include "physics/kernels/fast_car_lanes.hpp"

namespace groundsim::rigid {

using fastcar::BodyL;
using fastcar::cross3;
using fastcar::dot3;
using fastcar::invInertia;
using fastcar::Lane;
using BodyC = FastCarPlan::BodyC;

// What every solve reads besides the contact set.
template <class V> struct FrictionInput {
  const BodyC* bc;        // the bodies' constants
  BodyL<V>* bodies;       // their evaluation: Iw or c, F, T; vp and wp are written
  size_t nbodies;
  const V* Y;             // the state (13 per body)
  const V* brake;         // each axle's brake torque
  const double* t1;       // the plane's tangent basis
  const double* t2;
  double h;
  int iterations;
};

// The bodies' velocities after h under the forces so far (friction's start).
template <class V> GROUNDSIM_INLINE_BODY void predictVelocities(const FrictionInput<V>& in) {
  for (size_t i = 0; i < in.nbodies; ++i) {
    BodyL<V>& B = in.bodies[i];
    const V* y = in.Y + 13 * i;
    const double inv_m = in.bc[i].inv_mass;
    V Lh[3];
    for (int d = 0; d < 3; ++d) {
      B.vp[d] = y[7 + d] + in.h * B.F[d] * inv_m;
      Lh[d] = y[10 + d] + in.h * B.T[d];
    }
    invInertia(in.bc[i], B, Lh, B.wp);
  }
}

// Each solved slot's 2x2 tangential effective mass and its inverse, and
// the impulses' scale for the convergence test (with the brakes').
template <class V, class Set>
GROUNDSIM_INLINE_BODY V contactMasses(const FrictionInput<V>& in, const V t1[3], const V t2[3], Set& set) {
  using L = Lane<V>;
  V scale = L::all(0.0);
  for (size_t k = 0; k < set.slots(); ++k) {
    if (!set.solves(k)) continue;  // N is zero in every lane: adds zero
    auto& c = set.at(k);
    const int bi = set.body(k);
    const BodyL<V>& B = in.bodies[bi];
    const double inv_m = in.bc[bi].inv_mass;
    cross3(c.rr, t1, c.a1);
    cross3(c.rr, t2, c.a2);
    invInertia(in.bc[bi], B, c.a1, c.b1);
    invInertia(in.bc[bi], B, c.a2, c.b2);
    c.k01 = dot3(c.a1, c.b2);
    c.k00 = inv_m + dot3(c.a1, c.b1);
    c.k11 = inv_m + dot3(c.a2, c.b2);
    const V invdet = 1.0 / (c.k00 * c.k11 - c.k01 * c.k01);
    c.i00 = c.k11 * invdet;
    c.i10 = -c.k01 * invdet;
    c.i01 = -c.k01 * invdet;
    c.i11 = c.k00 * invdet;
    scale += set.mu(k) * c.N * in.h;
  }
  for (size_t w = 0; w < set.axles(); ++w) {
    const V b = in.brake[w];
    scale += (b < 0.0 ? L::all(0.0) : b) * in.h;
  }
  return scale;
}

// What a brake sweep needs of each axle's inertia: the same every sweep.
template <class V, class Set> GROUNDSIM_INLINE_BODY void axleInertias(const FrictionInput<V>& in, Set& set) {
  for (size_t w = 0; w < set.axles(); ++w) {
    const int b = set.axleBody(w), cr = set.axleCarrier(w);
    if (cr < 0) continue;
    auto& x = set.axle(w);
    invInertia(in.bc[b], in.bodies[b], x.a, x.ia);
    invInertia(in.bc[cr], in.bodies[cr], x.a, x.ic);
    x.bden = dot3(x.a, x.ia) + dot3(x.a, x.ic);
  }
}

// One sweep's brakes in the `active` lanes: each braked wheel's impulse
// about its axle, clamped to its torque times h, against its carrier.
template <class V, class Set>
GROUNDSIM_INLINE_BODY void brakeSweep(const FrictionInput<V>& in, typename Lane<V>::M active, Set& set, V& change,
                                      V& total) {
  using M = typename Lane<V>::M;
  for (size_t w = 0; w < set.axles(); ++w) {
    const int cr = set.axleCarrier(w);
    if (cr < 0) continue;
    auto& x = set.axle(w);
    BodyL<V>& B = in.bodies[set.axleBody(w)];
    BodyL<V>& C = in.bodies[cr];
    const V Bh = in.brake[w] * in.h;
    const V rel[3] = {B.wp[0] - C.wp[0], B.wp[1] - C.wp[1], B.wp[2] - C.wp[2]};
    const V spin = dot3(x.a, rel);
    V acc = x.bi - spin / x.bden;
    acc = acc < -Bh ? -Bh : (Bh < acc ? Bh : acc);
    const M on = active & (in.brake[w] > 0.0);
    acc = on ? acc : x.bi;
    const V d = acc - x.bi;
    x.bi = acc;
    change += d < 0.0 ? -d : d;
    total += acc < 0.0 ? -acc : acc;
    for (int k = 0; k < 3; ++k) {
      B.wp[k] += d * x.ia[k];
      C.wp[k] -= d * x.ic[k];
    }
  }
}

// One sweep's contacts in slot order (the general path's), in the
// `active` lanes: each contact's tangential impulse inside its friction disc.
template <class V, class Set>
GROUNDSIM_INLINE_BODY void contactSweep(const FrictionInput<V>& in, const V t1[3], const V t2[3],
                                        typename Lane<V>::M active, Set& set, V& change, V& total) {
  using L = Lane<V>;
  using M = typename L::M;
  for (size_t k = 0; k < set.slots(); ++k) {
    // a lane not `on` computes a zero change: it does not touch (impulse 0),
    // or it has converged and its change and total are no longer read
    if (!set.solves(k)) continue;
    auto& c = set.at(k);
    const M on = active & set.in(k);
    const int bi = set.body(k);
    BodyL<V>& B = in.bodies[bi];
    const V ut0 = dot3(t1, B.vp) + dot3(B.wp, c.a1);
    const V ut1 = dot3(t2, B.vp) + dot3(B.wp, c.a2);
    V acc0 = c.j0 - (c.i00 * ut0 + c.i01 * ut1);
    V acc1 = c.j1 - (c.i10 * ut0 + c.i11 * ut1);
    const V limit = set.mu(k) * c.N * in.h;
    const V an = L::sqrt(acc0 * acc0 + acc1 * acc1);
    const auto slide = an > limit;
    if (L::any(slide)) {
      // sliding: mu N opposite the slip this contact would have without
      // its own friction (velocity_constraints.cpp says why)
      const V free0 = ut0 - (c.k00 * c.j0 + c.k01 * c.j1);
      const V free1 = ut1 - (c.k01 * c.j0 + c.k11 * c.j1);
      const V fn = L::sqrt(free0 * free0 + free1 * free1);
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
    const double inv_m = in.bc[bi].inv_mass;
    for (int q = 0; q < 3; ++q) {
      B.vp[q] += (d0 * t1[q] + d1 * t2[q]) * inv_m;
      B.wp[q] += d0 * c.b1[q] + d1 * c.b2[q];
    }
  }
}

// The brake and friction impulses over the step become forces and torques.
template <class V, class Set>
GROUNDSIM_INLINE_BODY void impulsesAsForces(const FrictionInput<V>& in, bool any_brake, const V t1[3], const V t2[3],
                                            Set& set) {
  const double inv_h = 1.0 / in.h;
  if (any_brake) {
    for (size_t w = 0; w < set.axles(); ++w) {
      const int cr = set.axleCarrier(w);
      if (cr < 0) continue;
      const auto& x = set.axle(w);
      BodyL<V>& B = in.bodies[set.axleBody(w)];
      BodyL<V>& C = in.bodies[cr];
      const V tb = x.bi / in.h;
      for (int k = 0; k < 3; ++k) {
        B.T[k] += tb * x.a[k];
        C.T[k] -= tb * x.a[k];
      }
    }
  }
  for (size_t k = 0; k < set.slots(); ++k) {
    if (!set.solves(k)) continue;  // no impulse in any lane
    const auto& c = set.at(k);
    BodyL<V>& B = in.bodies[set.body(k)];
    V f[3], rf[3];
    for (int q = 0; q < 3; ++q) f[q] = (c.j0 * t1[q] + c.j1 * t2[q]) * inv_h;
    cross3(c.rr, f, rf);
    for (int q = 0; q < 3; ++q) {
      B.F[q] += f[q];
      B.T[q] += rf[q];
    }
  }
}

// Stick-slip friction and brakes (velocity_constraints.cpp): impulses that
// bring the contacts' slip and the braked wheels' spin to rest within h,
// bounded by mu N h and the brake torque times h, in sweeps until they
// settle; brakes first in each sweep, contacts in slot order; a lane whose
// sweeps have converged keeps its impulses. Returns the sweeps taken.
template <class V, class Set> GROUNDSIM_INLINE_BODY int frictionAndBrakes(const FrictionInput<V>& in, Set& set) {
  using L = Lane<V>;
  using M = typename L::M;
  M touching = set.touching();
  M braking = L::all(0.0) > 0.0;
  for (size_t w = 0; w < set.axles(); ++w) braking = braking | (in.brake[w] > 0.0);
  for (size_t k = 0; k < set.slots(); ++k) set.at(k).j0 = set.at(k).j1 = L::all(0.0);
  for (size_t w = 0; w < set.axles(); ++w) set.axle(w).bi = L::all(0.0);
  if (!L::any(touching) && !L::any(braking)) return 0;  // nothing to solve in any lane
  predictVelocities(in);
  const V t1[3] = {L::all(in.t1[0]), L::all(in.t1[1]), L::all(in.t1[2])};
  const V t2[3] = {L::all(in.t2[0]), L::all(in.t2[1]), L::all(in.t2[2])};
  const V scale = contactMasses(in, t1, t2, set);
  M active = touching | braking;
  const bool any_brake = L::any(braking);
  if (any_brake) axleInertias(in, set);
  int sweeps = 0;
  for (int iter = 0; iter < in.iterations; ++iter) {
    V change = L::all(0.0), total = L::all(0.0);
    if (any_brake) brakeSweep(in, active, set, change, total);
    contactSweep(in, t1, t2, active, set, change, total);
    sweeps = iter + 1;
    // converged: what is left cannot add up to creep
    active = L::andNot(active, pointwise::converged(change, total, scale));
    if (!L::any(active)) break;
  }
  impulsesAsForces(in, any_brake, t1, t2, set);
  return sweeps;
}

}  // namespace groundsim::rigid
