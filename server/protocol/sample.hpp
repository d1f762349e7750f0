// A received state_t as the physics' VehicleSample, the row `groundsim run`
// writes to CSV, so logged and embedded runs share one format.
#pragma once

#include <cstdint>

#include <groundsim/state_t.hpp>

#include "physics/checks/telemetry.hpp"

namespace groundsim::net {

VehicleSample toSample(const groundsim::state_t& m, int vehicle);

}  // namespace groundsim::net
