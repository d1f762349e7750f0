// Load-time estimate of the stiffest modes of a model, compared with the
// stability limit of its integrator (omega * dt < 2 (sqrt(1 + z^2) - z) for
// semi-implicit Euler and Verlet with damping ratio z, 2.83 for RK4; the
// implicit and adaptive methods have none). Penalty ground contact and
// springs are linear modes, so the estimate matches what runs do: the
// report's car (40 rim springs of 1e5 N/m per wheel) gives dt < 3.0e-4 s,
// and its code was stable at 3e-4 and diverged at 4e-4.
#pragma once

#include <string>
#include <vector>

#include "physics/core/model.hpp"

namespace groundsim {

// A step from this share of a mode's limit on is warned about ("near", and
// beyond 1 "beyond"); the accuracy pilot offers none at or above it.
inline constexpr double kStabilityMargin = 0.9;

struct StiffMode {
  std::string what;       // e.g. "ground contact of 'car/front_left'"
  double omega = 0.0;     // rad/s
  double zeta = 0.0;      // damping ratio
  double limit = 0.0;     // largest stable omega * dt for the integrator (inf: none)
  double dt_limit = 0.0;  // s, limit / omega
};

// The stiffest mode (largest omega*dt relative to its limit) per kind:
// ground contact alone, everything acting on one part together, and spring
// coupling between two parts. Empty for a model with none of them.
std::vector<StiffMode> stiffestModes(const Model& m);

// Human-readable warnings for modes at or beyond 90% of their limit, and
// for vehicles whose static sag reaches half the penetration limit.
std::vector<std::string> stabilityWarnings(const Model& m);

}  // namespace groundsim
