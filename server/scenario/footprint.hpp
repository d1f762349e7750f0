// A vehicle's footprint in the ground plane: the rectangle about its centre
// that holds its wheels and, for a road car, its body box (the collision
// shape). Two vehicles placed on the ground must not start with
// overlapping footprints (scene_builder.cpp refuses them); the rectangles,
// grown by what a task's draws may move and turn them, keep its drawn
// starts apart (experiments/task_context.cpp), so sedans stand 2.5 m
// abreast on a grid.
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

// Whether two vehicles' rectangles may overlap once each is moved by up to
// move_x and move_y (m, world x and y) and turned about its position by up
// to `turn` (rad), independently: false only when they cannot. Turns of
// pi/2 or more fall back to the circles about the rectangles.
bool footprintsMayMeet(const VehicleSpec& a, const VehicleSpec& b, double move_x, double move_y, double turn);

}  // namespace groundsim::scenario
