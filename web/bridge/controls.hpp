// The one place where the page's normalized controls become the server's
// commands: a road car (kind "road_car") takes them as they are (controls_t);
// other vehicles take per-wheel torques and steering angles (drive_t).
#pragma once

#include <string>

#include <groundsim/controls_t.hpp>
#include <groundsim/drive_t.hpp>

#include "physics/build/vehicle.hpp"

namespace groundsim::web {

// What a player's keys or gamepad produce, every value normalized.
struct Controls {
  double throttle = 0.0;   // 0..1
  double brake = 0.0;      // 0..1
  double steer = 0.0;      // -1 (full right) .. 1 (full left)
  bool handbrake = false;  // rear wheels braked fully
  int gear = 1;            // -1 reverse, 0 neutral, 1 drive
};

// Full-scale values of the mapping, per wheel, for the report's 1.4 kg car
// (wheels of 1 m, 0.1 kg; mu 0.5 carries about 1.7 N m per wheel before it
// slips): full throttle accelerates it at about 2.7 m/s^2 without spinning
// the wheels, full brake locks them.
struct ControlScale {
  double drive_torque = 1.2;  // N m  per wheel at full throttle
  double brake_torque = 6.0;  // N m  per wheel at full brake
  double steer = kFullLockRad;  // rad  front wheels at full lock (the server clamps to each wheel's limit)
};

// drive_t for one vehicle of four wheels (front-left, front-right, rear-left,
// rear-right), or one wheel for a lone wheel. Session, token and client are
// filled by the caller.
groundsim::drive_t toDrive(const Controls& c, int vehicle, int wheels, const ControlScale& scale = {});

// controls_t for a road car: throttle, brake and steer clamped to their
// ranges (the server refuses anything else); the page's gear 1 (drive) is
// the automatic gearbox, -1 reverse, 0 neutral. Session, token and client
// are filled by the caller.
groundsim::controls_t toCarControls(const Controls& c, int vehicle);

}  // namespace groundsim::web
