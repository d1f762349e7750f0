#include "tyre.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

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

void deflectionRates(const TyreParams& t, double vx, double vy, double omega_r, double ux, double uy,
                     double* dux, double* duy) {
  const double vsx = vx - omega_r, vsy = vy, avx = std::abs(vx);
  const double inv_sigma = 1.0 / t.relaxation_length;
  *dux = -vsx - (avx + 0.1 * std::abs(vsx)) * inv_sigma * ux;
  *duy = -vsy - (avx + 0.1 * std::abs(vsy)) * inv_sigma * uy;
}

}  // namespace groundsim
