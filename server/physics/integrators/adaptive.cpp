// Bogacki-Shampine 3(2) with error control (see integrator_methods.hpp).
//
// The tableau (Bogacki & Shampine 1989):
//   k1 = f(y), k2 = f(y + h/2 k1), k3 = f(y + 3h/4 k2),
//   y3 = y + h (2/9 k1 + 1/3 k2 + 4/9 k3)               third order
//   k4 = f(y3),  error = h (-5/72 k1 + 1/12 k2 + 1/9 k3 - 1/8 k4)
// k4 is the next substep's k1 (first same as last) when forces do not
// depend on the step; velocity-level friction and brakes are sized for the
// substep passed to computeForces, so with them k1 is re-evaluated whenever
// the substep changes. Each advance() starts from a fresh k1: a restored
// State then continues bit for bit (the only carried quantity is s.h_next).
// The controls are applied over each substep (appliesControls): steering
// moves at its rate and the gear's timer runs with the substeps, so they
// are refined with the error, not held for the output step; a rejected
// substep puts them back, and k1 is evaluated again when they moved.
#include <algorithm>
#include <cmath>

#include "physics/forces/controls.hpp"
#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"

namespace groundsim {
namespace {

constexpr double kSafety = 0.9;
constexpr double kMaxGrowth = 5.0;
constexpr double kMaxShrink = 0.2;
// Below this fraction of the output step a substep is accepted whatever its
// error: the run then diverges visibly (health check) instead of stalling.
constexpr double kMinFraction = 1e-9;

// max_i |e_i| / (tol (1 + max(|y_i|, |y3_i|))): absolute tolerance tol for
// small components (metres, m/s, unit quaternions), relative for large ones.
double errorNorm(const Eigen::VectorXd& e, const Eigen::VectorXd& y, const Eigen::VectorXd& y3, double tol) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < e.size(); ++i) {
    const double sc = tol * (1.0 + std::max(std::abs(y[i]), std::abs(y3[i])));
    const double r = std::abs(e[i]) / sc;
    if (!(r <= worst)) worst = r;  // NaN propagates as the worst
  }
  return worst;
}

}  // namespace

void Adaptive::advance(const Model& m, State& s, Workspace& ws, double h) {
  const double tol = m.opt.tolerance > 0.0 ? m.opt.tolerance : 1e-6;
  Eigen::VectorXd& y = s.y;
  Eigen::VectorXd& yt = ws.ytmp;
  Eigen::VectorXd& y3 = ws.k5;
  auto eval = [&](const Eigen::VectorXd& at, double step, Eigen::VectorXd& k) {
    computeForces(m, at, s.applied, step, ws);
    stateDerivative(m, at, ws, k);
    ++evaluations;
    return ws.drive_power;
  };

  double trial = (s.h_next > 0.0 && std::isfinite(s.h_next)) ? s.h_next : h;
  double remaining = h;
  bool k1_valid = false, k1_step_dependent = false;
  double k1_step = 0.0, p1 = 0.0;
  while (remaining > 0.0) {
    // (a last sliver of a few ulps is folded into this substep)
    const bool last = trial >= (1.0 - 1e-9) * remaining;
    const double hs = last ? remaining : trial;
    ws.applied_mark = s.applied;  // same sizes: no allocation
    ws.cars_mark = s.cars;
    applyControls(m, hs, s);
    ws.car_inputs = s.cars;
    if (!k1_valid || controlsMoved(ws.applied_mark, ws.cars_mark, s) || (k1_step_dependent && k1_step != hs)) {
      p1 = eval(y, hs, ws.k1);
      k1_step_dependent = forcesDependOnStep(m, s.applied, ws);
      k1_step = hs;
      k1_valid = true;
    }
    yt = y + (0.5 * hs) * ws.k1;
    const double p2 = eval(yt, hs, ws.k2);
    yt = y + (0.75 * hs) * ws.k2;
    const double p3 = eval(yt, hs, ws.k3);
    y3 = y + hs * ((2.0 / 9.0) * ws.k1 + (1.0 / 3.0) * ws.k2 + (4.0 / 9.0) * ws.k3);
    normalizeRotations(m, y3);
    const double p4 = eval(y3, hs, ws.k4);
    ws.err = hs * ((-5.0 / 72.0) * ws.k1 + (1.0 / 12.0) * ws.k2 + (1.0 / 9.0) * ws.k3 - 0.125 * ws.k4);
    const double e = errorNorm(ws.err, y, y3, tol);
    // third-order solution, second-order estimate: the error scales as hs^3
    const double factor = std::isfinite(e) ? std::clamp(kSafety * std::cbrt(1.0 / std::max(e, 1e-300)),
                                                        kMaxShrink, kMaxGrowth)
                                           : kMaxShrink;
    if (e <= 1.0 || hs <= kMinFraction * h) {
      y = y3;
      s.drive_work += hs * ((2.0 / 9.0) * p1 + (1.0 / 3.0) * p2 + (4.0 / 9.0) * p3);
      remaining = last ? 0.0 : remaining - hs;
      ++accepted;
      // a substep shortened to land on the end of h says little about the
      // step the solution allows: keep the longer trial unless this one
      // asks for less
      const double proposal = hs * factor;
      trial = last ? std::min(trial, proposal) : proposal;
      ws.k1.swap(ws.k4);  // first same as last
      p1 = p4;
      k1_step_dependent = forcesDependOnStep(m, s.applied, ws);
      k1_step = hs;
    } else {
      trial = hs * std::min(factor, 1.0);
      ++rejected;
      s.applied = ws.applied_mark;
      s.cars = ws.cars_mark;
    }
  }
  s.h_next = trial;
}

}  // namespace groundsim
