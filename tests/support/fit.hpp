// Least-squares slope of a body's speed over [t0, t1], sampled every 10 ms:
// the measured acceleration of a rolling or driven car.
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/simulator.hpp"

namespace groundsim::support {

inline double fittedAcceleration(Simulator& sim, double t0, double t1, int body = 0) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  int n = 0;
  const long long every = std::max<long long>(1, std::llround(0.01 / sim.model().opt.dt));
  while (sim.state().t < t1 - 1e-12) {
    if (!sim.step(every)) return std::nan("");
    if (sim.state().t < t0) continue;
    const double t = sim.state().t, v = bodyVel(sim.state().y, body).norm();
    st += t; sv += v; stt += t * t; stv += t * v; ++n;
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

}  // namespace groundsim::support
