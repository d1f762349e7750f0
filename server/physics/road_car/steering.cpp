#include <algorithm>
#include <cmath>

#include "physics/road_car/steering.hpp"

namespace groundsim {

void ackermannAngles(const SteeringParams& s, double wheelbase, double track, double delta, double* left,
                     double* right) {
  if (delta == 0.0 || s.ackermann == 0.0) {
    *left = *right = delta;
    return;
  }
  const double k = track / (2.0 * wheelbase);
  // sqrt(1 + k^2) sin(x - phi) = -k cos(2 delta), phi = atan k, x = 2 d
  const double x = std::atan(k) + std::asin(std::clamp(-k * std::cos(2.0 * delta) / std::sqrt(1.0 + k * k), -1.0, 1.0));
  const double d = s.ackermann * 0.5 * x;  // even in delta: the inner wheel turns more either way
  *left = delta + d;
  *right = delta - d;
}

}  // namespace groundsim
