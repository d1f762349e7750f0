// Observed order of convergence by self-convergence: the state at the end
// time with steps h, h/2, h/4 (no exact solution needed). The differences of
// successive solutions shrink by 2^p for a method of order p once h is in
// the asymptotic range. The whole state vector is compared (max norm): one
// coordinate can be integrated exactly by accident (a skid at constant
// deceleration is a parabola, which RK4 reproduces to round-off).
#pragma once

#include <cmath>
#include <functional>

#include <Eigen/Core>

namespace groundsim::support {

struct ObservedOrder {
  double order = 0.0;              // log2 of the difference ratio
  double coarse = 0.0, fine = 0.0; // |y(h) - y(h/2)|, |y(h/2) - y(h/4)| (max norm)
};

// yT(h): the state at the end time with step h.
inline ObservedOrder selfConvergence(const std::function<Eigen::VectorXd(double)>& yT, double h) {
  const Eigen::VectorXd a = yT(h), b = yT(h / 2), c = yT(h / 4);
  ObservedOrder o;
  o.coarse = (a - b).lpNorm<Eigen::Infinity>();
  o.fine = (b - c).lpNorm<Eigen::Infinity>();
  o.order = std::log2(o.coarse / o.fine);
  return o;
}

}  // namespace groundsim::support
