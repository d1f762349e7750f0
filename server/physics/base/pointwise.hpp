// The pointwise formulas of the rigid-body physics, written once for every
// step path: the general loop (forces/), the circle-car kernel
// (kernels/fast_car_kernel.hpp, for each of its lane types) and the ring
// car (kernels/ring_car.cpp). T is double or a GCC vector of doubles (a
// comparison then gives a lane mask and `?:` picks lane by lane), so the
// paths differ in how they loop, never in what they compute per point.
// Structure review, section 1: the zero-length guard, the rotation series
// and the convergence test had drifted apart in three copies.
#pragma once

namespace groundsim::pointwise {

// Below this squared length (m^2) a spring has no direction: no force.
inline constexpr double kMinSpringLength2 = 1e-24;

// Report eq. (1), the dashpot on the rate of change of length: the force on
// a spring's first point per unit of d = x_b - x_a, so that a gets t d and b
// gets -t d: t = (k (|d| - rest) + c (d . e) / |d|) / |d|, e = u_b - u_a.
// inv: 1 / |d| as the caller computes it (a floor under |d|^2 keeps it
// finite where the guard then gives 0).
template <class T, class K>
inline T springTension(T len2, T inv, T d_dot_e, K k, K c, K rest) {
  const T rate = d_dot_e * inv;
  const T t = (k * (len2 * inv - rest) + c * rate) * inv;
  return len2 > kMinSpringLength2 ? t : T{};
}

// The same for loops that must stay branch-free to vectorise (the rims'
// fans): the guard as a multiplication by 0 or 1. GCC if-converts the
// compare (and so vectorises the loop) only where FP compares are assumed
// not to trap: kernels/ring_car.cpp is built with -fno-trapping-math
// (server/physics/CMakeLists.txt).
inline double springTensionFan(double len2, double inv, double d_dot_e, double k, double c, double rest) {
  const double rate = d_dot_e * inv;
  const double t = (k * (len2 * inv - rest) + c * rate) * inv;
  return t * static_cast<double>(len2 > kMinSpringLength2);
}

// Report eq. (10) with damping: the normal force of a penalty contact at
// `depth` whose depth grows at `rate`; Kelvin-Voigt S d + c rate, or
// Hunt-Crossley S d (1 + alpha rate), whose damping vanishes at first
// touch. Never pulling.
template <class T, class P>
inline T penaltyNormal(P stiffness, T depth, P damping, T rate, bool hunt_crossley) {
  T N = stiffness * depth;
  N = hunt_crossley ? T(N * (1.0 + damping * rate)) : T(N + damping * rate);
  return N < 0.0 ? T{} : N;
}

// The velocity-level friction solve has converged when a sweep changed the
// impulses by at most 1e-6 of their total plus 1e-9 of the problem's scale:
// what is left cannot add up to creep (a parked car then slides about
// 1e-6 g sin(slope) h, docs/accuracy.md).
template <class T, class S>
inline auto converged(T change, T total, S scale) {
  return change <= 1e-6 * total + 1e-9 * scale;
}

// cos(a/2) and sin(a/2)/a from a^2, for a rotation by the vector w (a =
// |w|) as a quaternion (cos(a/2), sin(a/2)/a w). Below kRotationSeries the
// series to a^6 (the next terms, a^8 / 1e7, are below round-off) spares
// two library calls per body and step; every path takes the same series.
inline constexpr double kRotationSeries = 1e-3;  // rad^2
template <class T>
inline void halfAngleSeries(T a2, T& c, T& s) {
  c = 1.0 + a2 * (-0.125 + a2 * (1.0 / 384.0 - a2 * (1.0 / 46080.0)));
  s = 0.5 + a2 * (-1.0 / 48.0 + a2 * (1.0 / 3840.0 - a2 * (1.0 / 645120.0)));
}

}  // namespace groundsim::pointwise
