// A vehicle's footprint in the ground plane: the rectangle about its centre
// that holds its wheels and, for a road car, its body box (the collision
// shape). Two vehicles placed on the ground must not start with
// overlapping footprints (scene_builder.cpp refuses them); the circle
// about the rectangle keeps a task's drawn starts apart
// (experiments/task_context.cpp), whatever their drawn headings.
#pragma once

#include "scenario/vehicle_spec.hpp"

namespace groundsim::scenario {

struct Footprint {
  double front = 0.0, back = 0.0;  // m  ahead of and behind the centre, along the heading
  double half_width = 0.0;         // m  to either side
};

Footprint vehicleRectangle(const VehicleSpec& v);

// The radius of the circle about the centre that holds the rectangle.
double vehicleFootprint(const VehicleSpec& v);

// Whether two vehicles' rectangles, placed at their positions and yaws,
// overlap in the ground plane (separating axis test).
bool footprintsOverlap(const VehicleSpec& a, const VehicleSpec& b);

}  // namespace groundsim::scenario
