// Adds a road car (road_car.hpp) to a model under construction.
#pragma once

#include <string>

#include "physics/road_car/road_car.hpp"
#include "physics/build/vehicle.hpp"

namespace groundsim {

// Placed like the report's car: with on_ground, aligned with the ground
// normal below at.position and standing on its wheels at design ride
// height (the springs preloaded by the static corner loads, so it starts
// at rest); at.speed rolls it forward with every wheel turning at speed / r
// (plus at.wheel_spin).
CarHandle addRoadCar(ModelBuilder& b, const std::string& name, const RoadCarParams& p, const CarPlacement& at);

}  // namespace groundsim
