// The slip-based tyre (see tyre.cpp): Magic Formula shape from physical
// figures, combined slip, and the deflection (relaxation) states.
#pragma once

#include <cmath>

#include "physics/road_car/road_car.hpp"

namespace groundsim {

// Pacejka's F = D sin(C atan(B x - E (B x - atan(B x)))).
struct MagicFormula {
  double B = 0.0, C = 1.0, D = 0.0, E = 0.0;
  double operator()(double x) const;
};

// The shape with slope `stiffness` at zero slip, peak `peak` at slip
// `peak_slip` and the large-slip asymptote `sliding_ratio * peak`:
// C = 2 - (2/pi) asin(sliding_ratio), B = stiffness / (C D), E from the peak.
MagicFormula fitMagicFormula(double stiffness, double peak, double peak_slip, double sliding_ratio);
// The same with C and tan(pi / (2 C)) given (they depend on sliding_ratio only).
MagicFormula fitMagicFormula(double stiffness, double peak, double peak_slip, double C, double tan_peak);
double shapeFactor(double sliding_ratio);

// Stiffness at load F_z: C0 z (1 - e (z - 1)), z = F_z / F_z0, never below 0.
double loadedStiffness(double c0, double load_sensitivity, double Fz, double Fz0);

// Tyre forces (tyre frame, N) from the transient slips kx = u_x / sigma
// (~ slip ratio) and ky = u_y / sigma (~ -tan slip angle) at load Fz and
// peak friction mu: each direction's pure-slip curve evaluated at the
// combined normalised slip rho = |(kx / kappa_peak, ky / tan alpha_peak)|,
// shared out in proportion (friction circle at large slip, exact pure slip).
void tyreForces(const TyreParams& t, double Fz, double Fz0, double mu, double kx, double ky, double* Fx,
                double* Fy);

// tyreForces of four tyres at once (a lane not `on` gives 0, 0). Where
// `wide` the same arithmetic with the eight curves' atan and sin taken four
// at a time (vector_math.hpp: within a few ulp of libm's) and reciprocals
// of the fixed figures (rounding); otherwise tyreForces lane by lane.
struct TyreLanes {
  const TyreParams* t[4] = {nullptr, nullptr, nullptr, nullptr};
  double Fz[4] = {}, Fz0[4] = {}, inv_Fz0[4] = {}, mu[4] = {}, kx[4] = {}, ky[4] = {};
  bool on[4] = {};
};
void tyreForces4(const TyreLanes& in, bool wide, double* Fx, double* Fy);

// Deflection rates of the relaxation model (Pacejka 2006, 7.2):
// du/dt = -V_s - (V_r / sigma) u, V_s = (v_x - omega r, v_y) the slip
// velocity, V_r = |v_x| + |V_s| / 10. At standstill the deflection is a
// spring (no creep); rolling, u / sigma relaxes to the slip over sigma of
// travel; the |V_s| / 10 term bounds u / sigma by 10 when sliding at
// standstill (so a sliding tyre never winds up an unbounded deflection).
// (inline: the road car's wide and generic builds each take it in)
inline void deflectionRates(const TyreParams& t, double vx, double vy, double omega_r, double ux, double uy,
                            double* dux, double* duy) {
  const double vsx = vx - omega_r, vsy = vy, avx = std::abs(vx);
  const double inv_sigma = t.inv_relaxation > 0.0 ? t.inv_relaxation : 1.0 / t.relaxation_length;
  *dux = -vsx - (avx + 0.1 * std::abs(vsx)) * inv_sigma * ux;
  *duy = -vsy - (avx + 0.1 * std::abs(vsy)) * inv_sigma * uy;
}

}  // namespace groundsim
