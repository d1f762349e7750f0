// The radius of a vehicle's footprint about its centre in the ground plane:
// the circle two vehicles' placements must not overlap (scene_builder.cpp
// refuses them; a task with several agents keeps its drawn starts apart
// with it, experiments/task_context.cpp).
#pragma once

#include "scenario/vehicle_spec.hpp"

namespace groundsim::scenario {

double vehicleFootprint(const VehicleSpec& v);

}  // namespace groundsim::scenario
