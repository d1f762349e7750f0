#include "physics/road_car/tyre.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "physics/simd/simd_path.hpp"
#include "physics/simd/vector_math.hpp"

namespace groundsim {

double MagicFormula::operator()(double x) const {
  const double bx = B * x;
  return D * std::sin(C * std::atan(bx - E * (bx - std::atan(bx))));
}

double shapeFactor(double sliding_ratio) {
  // the asymptote for E < 1 is D sin(C pi / 2); C in (1, 2) puts it below the peak
  return 2.0 - (2.0 / std::numbers::pi) * std::asin(std::clamp(sliding_ratio, 0.05, 0.999));
}

MagicFormula fitMagicFormula(double stiffness, double peak, double peak_slip, double sliding_ratio) {
  const double C = shapeFactor(sliding_ratio);
  return fitMagicFormula(stiffness, peak, peak_slip, C, std::tan(std::numbers::pi / (2.0 * C)));
}

MagicFormula fitMagicFormula(double stiffness, double peak, double peak_slip, double C, double target) {
  MagicFormula f;
  f.D = peak;
  f.C = C;
  if (!(peak > 0.0) || !(stiffness > 0.0)) {
    f.B = 0.0;
    return f;
  }
  f.B = stiffness / (f.C * f.D);
  // the peak is where C atan(...) = pi/2: B x_m - E (B x_m - atan B x_m) = tan(pi / (2C))
  const double bx = f.B * peak_slip;
  const double denom = bx - std::atan(bx);
  f.E = denom > 1e-9 ? std::clamp((bx - target) / denom, -20.0, 0.95) : 0.0;
  return f;
}

double loadedStiffness(double c0, double e, double Fz, double Fz0) {
  const double z = Fz / Fz0;
  return std::max(0.0, c0 * z * (1.0 - e * (z - 1.0)));
}

void tyreForces(const TyreParams& t, double Fz, double Fz0, double mu, double kx, double ky, double* Fx,
                double* Fy) {
  *Fx = *Fy = 0.0;
  if (!(Fz > 0.0)) return;
  const double peak = mu * t.friction_scale * Fz;
  const double cx = loadedStiffness(t.longitudinal_stiffness, t.load_sensitivity, Fz, Fz0);
  const double cy = loadedStiffness(t.cornering_stiffness, t.load_sensitivity, Fz, Fz0);
  const double xm = t.peak_slip_ratio, ym = t.peak_slip_angle;  // tan alpha ~ alpha at the peak
  const double sx = kx / xm, sy = ky / ym;
  const double rho = std::sqrt(sx * sx + sy * sy);
  if (rho < 1e-9) {  // linear limit of both curves
    *Fx = cx * kx;
    *Fy = cy * ky;
    return;
  }
  // C depends on the sliding ratio only: one asin and one tan per call
  const double C = t.shape_c > 0.0 ? t.shape_c : shapeFactor(t.sliding_ratio);
  const double tp = t.shape_c > 0.0 ? t.shape_tan : std::tan(std::numbers::pi / (2.0 * C));
  const MagicFormula mx = fitMagicFormula(cx, peak, xm, C, tp);
  const MagicFormula my = fitMagicFormula(cy, peak, ym, C, tp);
  *Fx = (sx / rho) * mx(rho * xm);
  *Fy = (sy / rho) * my(rho * ym);
}

namespace {

// tyreForces' arithmetic for four tyres, with reciprocals where it divides
// by fixed figures (the nominal load, the peak slips) or twice by one value
GROUNDSIM_WIDE void tyreForcesWide(const TyreLanes& in, double* Fx, double* Fy) {
  // lanes 0-3: the wheels' longitudinal curves, 4-7 their lateral ones; a
  // lane with B = 0 evaluates to 0 (atan 0 = sin 0 = 0)
  alignas(32) double B[8], C[8], D[8], tp[8], slip_peak[8], x[8], share[8];
  bool curve[4];
  for (int i = 0; i < 4; ++i) {
    Fx[i] = Fy[i] = 0.0;
    curve[i] = false;
    for (int d : {i, i + 4}) B[d] = 0.0, C[d] = 1.0, D[d] = 0.0, tp[d] = 0.0, slip_peak[d] = 0.0, x[d] = 0.0,
                             share[d] = 0.0;
    const double Fz = in.Fz[i];
    if (!in.on[i] || !(Fz > 0.0)) continue;
    const TyreParams& t = *in.t[i];
    const double peak = in.mu[i] * t.friction_scale * Fz;
    const double z = Fz * in.inv_Fz0[i], load = z * (1.0 - t.load_sensitivity * (z - 1.0));
    const double cx = std::max(0.0, t.longitudinal_stiffness * load);
    const double cy = std::max(0.0, t.cornering_stiffness * load);
    const double xm = t.peak_slip_ratio, ym = t.peak_slip_angle;
    const double sx = in.kx[i] * t.inv_peak_slip_ratio, sy = in.ky[i] * t.inv_peak_slip_angle;
    const double rho = std::sqrt(sx * sx + sy * sy);
    if (rho < 1e-9) {
      Fx[i] = cx * in.kx[i];
      Fy[i] = cy * in.ky[i];
      continue;
    }
    curve[i] = true;
    const double inv_rho = 1.0 / rho;
    const double c = t.shape_c, inv_cp = 1.0 / (c * peak);
    const double stiff[2] = {cx, cy}, m[2] = {xm, ym}, s[2] = {sx, sy};
    for (int k = 0; k < 2; ++k) {
      const int d = i + 4 * k;
      C[d] = c;
      D[d] = peak;
      tp[d] = t.shape_tan;
      slip_peak[d] = m[k];
      x[d] = rho * m[k];
      share[d] = s[k] * inv_rho;
      if (peak > 0.0 && stiff[k] > 0.0) B[d] = stiff[k] * inv_cp;
    }
  }
  // fitMagicFormula's E, then MagicFormula::operator() at x
  alignas(32) double bp[8], E[8], bx[8], a[8];
  for (int d = 0; d < 8; ++d) bp[d] = B[d] * slip_peak[d];
  atan4(bp, a, true);
  atan4(bp + 4, a + 4, true);
  for (int d = 0; d < 8; ++d) {
    const double denom = bp[d] - a[d];
    E[d] = B[d] != 0.0 && denom > 1e-9 ? std::clamp((bp[d] - tp[d]) / denom, -20.0, 0.95) : 0.0;
    bx[d] = B[d] * x[d];
  }
  atan4(bx, a, true);
  atan4(bx + 4, a + 4, true);
  for (int d = 0; d < 8; ++d) a[d] = bx[d] - E[d] * (bx[d] - a[d]);
  atan4(a, a, true);
  atan4(a + 4, a + 4, true);
  for (int d = 0; d < 8; ++d) a[d] = C[d] * a[d];
  sin4(a, a, true);
  sin4(a + 4, a + 4, true);
  for (int i = 0; i < 4; ++i)
    if (curve[i]) {
      Fx[i] = share[i] * (D[i] * a[i]);
      Fy[i] = share[i + 4] * (D[i + 4] * a[i + 4]);
    }
}

}  // namespace

void tyreForces4(const TyreLanes& in, bool wide, double* Fx, double* Fy) {
  // the wide path reads the reciprocals and shape set when the car is built
  bool built = true;
  for (int i = 0; i < 4; ++i)
    if (in.on[i]) built = built && in.t[i]->shape_c > 0.0 && in.t[i]->inv_peak_slip_ratio > 0.0 && in.inv_Fz0[i] > 0.0;
  if (wide && built && vectorMathAvailable()) return tyreForcesWide(in, Fx, Fy);
  for (int i = 0; i < 4; ++i) {
    Fx[i] = Fy[i] = 0.0;
    if (in.on[i]) tyreForces(*in.t[i], in.Fz[i], in.Fz0[i], in.mu[i], in.kx[i], in.ky[i], &Fx[i], &Fy[i]);
  }
}

}  // namespace groundsim
