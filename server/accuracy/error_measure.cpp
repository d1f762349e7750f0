#include "accuracy/error_measure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace groundsim::accuracy {

double distanceTravelled(const Trajectory& t, int v, size_t samples) {
  double d = 0.0;
  for (size_t k = 1; k < std::min(samples, t.positions.size()); ++k)
    d += (t.positions[k][static_cast<size_t>(v)] - t.positions[k - 1][static_cast<size_t>(v)]).norm();
  return d;
}

RunError compareRuns(const Trajectory& a, const Trajectory& ref, size_t upto) {
  RunError e;
  if (!a.healthy || !ref.healthy) {
    e.path = e.speed = std::numeric_limits<double>::infinity();
    return e;
  }
  const size_t all = std::min(a.positions.size(), ref.positions.size());
  const size_t samples = std::min(all, upto);
  const bool whole = samples == all;
  const size_t vehicles = ref.final_velocity.size();
  double worst = -1.0;
  for (size_t v = 0; v < vehicles; ++v) {
    double gap = 0.0;
    for (size_t k = 0; k < samples; ++k) gap = std::max(gap, (a.positions[k][v] - ref.positions[k][v]).norm());
    const double path = gap / std::max(distanceTravelled(ref, static_cast<int>(v), samples), kMinDistance);
    double speed = 0.0;
    if (whole && v < a.final_velocity.size()) {
      const double vref = ref.final_velocity[v].norm();
      speed = std::abs(a.final_velocity[v].norm() - vref) / std::max(vref, kMinSpeed);
    }
    e.path = std::max(e.path, path);
    e.speed = std::max(e.speed, speed);
    if (std::max(path, speed) > worst) {
      worst = std::max(path, speed);
      e.vehicle = static_cast<int>(v);
    }
  }
  return e;
}

}  // namespace groundsim::accuracy
