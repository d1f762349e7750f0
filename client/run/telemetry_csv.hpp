// CSV rows of vehicle telemetry. Shared by `groundsim run` and the network
// logger so that files from either have identical columns:
//   t,x,y,z,vx,vy,vz,speed,vehicle,qw,qx,qy,qz,wx,wy,wz,
//   spin_fl..spin_rr,normal_fl..,friction_fl..,slip_fl..,energy,health,
//   gear,engine_rpm,drive_power,yaw_rate,slip_ratio_fl..,slip_angle_fl..,travel_fl..,
//   error_estimate
// (the last group is a road car's: gear 1..n / -1 reverse / 0 neutral,
// rpm, W at the wheels, rad/s about the body's vertical, slip ratio,
// slip angle rad, suspension travel m with + = compression; 0 otherwise;
// error_estimate: the run's live error estimate, the error measure of
// docs/accuracy.md, empty when the run has none)
// Units: s, m, m/s, quaternion body->world, rad/s (world), wheel spin rad/s
// about the axle relative to the body, forces N, slip m/s, energy J (whole
// scene), health one of ok|non_finite|... (physics healthName).
// Rows never contain NaN or inf: a non-finite number is written as an empty
// field (a missing value to every CSV reader).
#pragma once

#include <limits>
#include <string>

#include "physics/checks/telemetry.hpp"

namespace groundsim::cli {

std::string csvHeader();  // no trailing newline
// no trailing newline; error_estimate NaN: an empty field
std::string csvRow(const groundsim::VehicleSample& s, const std::string& vehicle_name,
                   double error_estimate = std::numeric_limits<double>::quiet_NaN());

}  // namespace groundsim::cli
