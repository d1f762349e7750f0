// The validated `vehicle` section: the physics car builder's parameters and
// placement, plus the constant controls the scene starts with.
#pragma once

#include <string>
#include <vector>

#include "physics/road_car/road_car.hpp"
#include "physics/build/vehicle.hpp"

namespace groundsim::scenario {

enum class DriveWheels { All, Front, Rear };

struct VehicleControlSpec {
  double drive_torque = 0.0;        // N m    per driven wheel, constant
  DriveWheels drive_wheels = DriveWheels::All;
  double brake_torque = 0.0;        // N m    per wheel, largest the brake may exert
  double steer = 0.0;               // rad    front wheels
};

// One row of a road car's `controls` table, with the fields earlier rows set
// held (road_car_section.cpp).
struct TimedControls {
  double t = 0.0;                   // s      from this time on
  CarControls controls;
};

struct VehicleSpec {
  std::string name = "car";
  bool lone_wheel = false;  // "kind": "wheel": one wheel, no body (wheel_* keys and initial only)
  CarParams params;
  CarPlacement placement;
  VehicleControlSpec control;
  bool road_car = false;    // "kind": "road_car": the keys of road_car_section.cpp instead of the report car's
  RoadCarParams road;
  std::vector<TimedControls> controls;  // road car only; empty: none (all zero)
};

}  // namespace groundsim::scenario
