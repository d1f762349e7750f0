// Largest stable step per integrator at the extremes, found by bisection in
// log(dt), with linear theory alongside where it has an answer.
#pragma once

#include <string>
#include <vector>

#include "physics/core/model.hpp"

namespace groundsim::accuracy {

struct StabilityRow {
  std::string family;      // ground_stiffness, mass_ratio, speed, drop_100m, slope, hour
  std::string parameter;   // "k=1e4 N/m", "ratio=1e3", ...
  IntegratorKind integrator;
  double largest_dt = 0;   // s, largest stable step found (inf: stable at every step tried)
  double theory_dt = 0;    // s, linear bound (0: none)
  double omega = 0;        // rad/s, the stiffest mode (0: not defined)
  std::string note;
};

// The whole map; `quick` trims the grids (for smoke runs).
std::vector<StabilityRow> stabilityMap(bool quick);

}  // namespace groundsim::accuracy
