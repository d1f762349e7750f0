// The validated `vehicle` section: the physics car builder's parameters and
// placement, plus the constant controls the scene starts with.
#pragma once

#include <string>

#include "physics/vehicle.hpp"

namespace groundsim::scenario {

enum class DriveWheels { All, Front, Rear };

struct VehicleControlSpec {
  double drive_torque = 0.0;        // N m    per driven wheel, constant
  DriveWheels drive_wheels = DriveWheels::All;
  double brake_torque = 0.0;        // N m    per wheel, largest the brake may exert
  double steer = 0.0;               // rad    front wheels
};

struct VehicleSpec {
  std::string name = "car";
  bool lone_wheel = false;  // "kind": "wheel": one wheel, no body (wheel_* keys and initial only)
  CarParams params;
  CarPlacement placement;
  VehicleControlSpec control;
};

}  // namespace groundsim::scenario
