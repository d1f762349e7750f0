// The ring car's stick-slip friction and brakes (ring_car.cpp's evaluation,
// after the normal forces and drive torques): the bodies' velocities
// predicted over h, each contact's tangential mass, then sweeps of brake
// and contact impulses until they settle, turned into forces. Always
// inlined into the step's wide and generic wrappers (ring_car.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "physics/base/pointwise.hpp"
#include "physics/core/state.hpp"
#include "physics/kernels/fast_car_lanes.hpp"
#include "physics/kernels/ring_car_detail.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim::ringcar {

using fastcar::cross3;
using fastcar::dot3;
using fastcar::mat3vec;

// The bodies' velocities after h under the forces so far (friction's start).
GROUNDSIM_INLINE_BODY void predictVelocities(const Plan& P, const double* Y, double h, Scratch& S) {
  for (size_t i = 0; i < P.rigid.bodies.size(); ++i) {
    BodyL<double>& B = S.rigid.bodies[i];
    const double* y = Y + 13 * i;
    double Lh[3];
    for (int d = 0; d < 3; ++d) {
      B.vp[d] = y[7 + d] + h * B.F[d] * P.rigid.bodies[i].inv_mass;
      Lh[d] = y[10 + d] + h * B.T[d];
    }
    mat3vec(B.Iw, Lh, B.wp);
  }
}

// Each contact's 2x2 tangential effective mass and its inverse; returns
// the impulses' scale for the convergence test.
GROUNDSIM_INLINE_BODY double contactMasses(const Plan& P, const std::vector<WheelControl>& ctl, double h,
                                           Scratch& S) {
  double scale = 0.0;
  for (ContactR& c : S.contacts()) {
    const BodyL<double>& B = S.rigid.bodies[c.body];
    const double inv_m = P.rigid.bodies[c.body].inv_mass;
    cross3(c.r, P.t1, c.a1);
    cross3(c.r, P.t2, c.a2);
    mat3vec(B.Iw, c.a1, c.b1);
    mat3vec(B.Iw, c.a2, c.b2);
    c.k01 = dot3(c.a1, c.b2);
    c.k00 = inv_m + dot3(c.a1, c.b1);
    c.k11 = inv_m + dot3(c.a2, c.b2);
    const double invdet = 1.0 / (c.k00 * c.k11 - c.k01 * c.k01);
    c.i00 = c.k11 * invdet;
    c.i01 = c.i10 = -c.k01 * invdet;
    c.i11 = c.k00 * invdet;
    scale += c.mu * c.N * h;
  }
  for (size_t w = 0; w < P.wheels.size(); ++w) scale += std::max(ctl[w].brake_torque, 0.0) * h;
  return scale;
}

// One sweep's brakes: each braked wheel's impulse about its axle, clamped
// to its torque times h, against its carrier. Adds to change and total.
GROUNDSIM_INLINE_BODY void brakeSweep(const Plan& P, const std::vector<WheelControl>& ctl, double h, Scratch& S,
                                      double& change, double& total) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const WheelC& wc = P.wheels[w];
    const double Bt = ctl[w].brake_torque;
    if (!(Bt > 0.0) || wc.carrier < 0) continue;
    BodyL<double>& B = bodies[wc.body];
    BodyL<double>& C = bodies[wc.carrier];
    const double* a = S.axis[w];
    double ia[3], ic[3];
    mat3vec(B.Iw, a, ia);
    mat3vec(C.Iw, a, ic);
    const double rel[3] = {B.wp[0] - C.wp[0], B.wp[1] - C.wp[1], B.wp[2] - C.wp[2]};
    const double acc = std::clamp(S.brake_impulse[w] - dot3(a, rel) / (dot3(a, ia) + dot3(a, ic)), -Bt * h, Bt * h);
    const double d = acc - S.brake_impulse[w];
    S.brake_impulse[w] = acc;
    change += std::abs(d);
    total += std::abs(acc);
    for (int k = 0; k < 3; ++k) {
      B.wp[k] += d * ia[k];
      C.wp[k] -= d * ic[k];
    }
  }
}

// One sweep's contacts: each contact's tangential impulse, inside its
// friction disc. Adds to change and total.
GROUNDSIM_INLINE_BODY void contactSweep(const Plan& P, double h, Scratch& S, double& change, double& total) {
  for (ContactR& c : S.contacts()) {
    BodyL<double>& B = S.rigid.bodies[c.body];
    const double ut0 = dot3(P.t1, B.vp) + dot3(B.wp, c.a1);
    const double ut1 = dot3(P.t2, B.vp) + dot3(B.wp, c.a2);
    double acc0 = c.j0 - (c.i00 * ut0 + c.i01 * ut1);
    double acc1 = c.j1 - (c.i10 * ut0 + c.i11 * ut1);
    const double limit = c.mu * c.N * h;
    const double an = std::sqrt(acc0 * acc0 + acc1 * acc1);
    if (an > limit) {
      // sliding: mu N opposite the slip this contact would have without
      // its own friction (velocity_constraints.cpp says why)
      const double free0 = ut0 - (c.k00 * c.j0 + c.k01 * c.j1);
      const double free1 = ut1 - (c.k01 * c.j0 + c.k11 * c.j1);
      const double fn = std::sqrt(free0 * free0 + free1 * free1);
      if (fn > 1e-12) {
        acc0 = -limit / fn * free0;
        acc1 = -limit / fn * free1;
      } else {
        acc0 *= limit / an;
        acc1 *= limit / an;
      }
    }
    const double d0 = acc0 - c.j0, d1 = acc1 - c.j1;
    c.j0 = acc0;
    c.j1 = acc1;
    change += std::abs(d0) + std::abs(d1);
    total += std::abs(acc0) + std::abs(acc1);
    const double inv_m = P.rigid.bodies[c.body].inv_mass;
    for (int q = 0; q < 3; ++q) {
      B.vp[q] += (d0 * P.t1[q] + d1 * P.t2[q]) * inv_m;
      B.wp[q] += d0 * c.b1[q] + d1 * c.b2[q];
    }
  }
}

// The brake and friction impulses as forces and torques over h.
GROUNDSIM_INLINE_BODY void impulsesAsForces(const Plan& P, double h, bool braking, Scratch& S) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  for (size_t w = 0; braking && w < P.wheels.size(); ++w) {
    const WheelC& wc = P.wheels[w];
    if (S.brake_impulse[w] == 0.0 || wc.carrier < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const double tq = S.brake_impulse[w] / h * S.axis[w][k];
      bodies[wc.body].T[k] += tq;
      bodies[wc.carrier].T[k] -= tq;
    }
  }
  for (const ContactR& c : S.contacts()) {
    BodyL<double>& B = bodies[c.body];
    double f[3], rf[3];
    for (int q = 0; q < 3; ++q) f[q] = (c.j0 * P.t1[q] + c.j1 * P.t2[q]) / h;
    cross3(c.r, f, rf);
    for (int q = 0; q < 3; ++q) {
      B.F[q] += f[q];
      B.T[q] += rf[q];
    }
  }
}

// Stick-slip friction and brakes (velocity_constraints.cpp): impulses that
// bring the contacts' slip and the braked wheels' spin to rest within h,
// bounded by mu N h and the brake torque times h, in sweeps until they settle.
GROUNDSIM_INLINE_BODY void frictionAndBrakes(const Plan& P, const double* Y, const std::vector<WheelControl>& ctl,
                                             double h, bool braking, Scratch& S) {
  S.sweeps = 0;
  for (size_t w = 0; w < P.wheels.size(); ++w) S.brake_impulse[w] = 0.0;
  if (S.ncon == 0 && !braking) return;
  predictVelocities(P, Y, h, S);
  const double scale = contactMasses(P, ctl, h, S);
  for (int iter = 0; iter < P.friction_iterations; ++iter) {
    double change = 0.0, total = 0.0;
    if (braking) brakeSweep(P, ctl, h, S, change, total);
    contactSweep(P, h, S, change, total);
    S.sweeps = iter + 1;
    if (pointwise::converged(change, total, scale)) break;
  }
  impulsesAsForces(P, h, braking, S);
}

}  // namespace groundsim::ringcar
