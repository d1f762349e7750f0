// What the outside world sees of one vehicle at one instant: the numbers
// the CLI writes to CSV and the server publishes. Plain data, no I/O.
#pragma once

#include <array>
#include <string>

#include "physics/simulator.hpp"

namespace groundsim {

struct WheelSample {
  double spin = 0.0;         // rad/s  about its axle, relative to the carrier
  double normal_force = 0.0; // N      ground normal force on the wheel
  double friction_force = 0.0;  // N   magnitude of the ground friction force
  double slip = 0.0;         // m/s    largest tangential speed of its contact points
  bool in_contact = false;
  // road cars only (0 otherwise)
  double slip_ratio = 0.0;   // -      (omega r - v_x) / |v_x|
  double slip_angle = 0.0;   // rad    atan(v_y / |v_x|) at the contact
  double travel = 0.0;       // m      suspension travel, + = compression
};

struct VehicleSample {
  double t = 0.0;            // s
  long long tick = 0;
  Vec3 position = Vec3::Zero();         // m     body centre of mass
  Quat orientation = Quat::Identity();  //       body to world
  Vec3 velocity = Vec3::Zero();         // m/s
  Vec3 angular_velocity = Vec3::Zero(); // rad/s world
  double speed = 0.0;                   // m/s   |velocity|
  std::array<WheelSample, 4> wheels{};  // front-left, front-right, rear-left, rear-right
  int wheel_count = 0;
  double yaw_rate = 0.0;     // rad/s  about the body's vertical axis
  // road cars only (0 otherwise)
  int gear = 0;              // -      engaged: 1..n, -1 reverse, 0 neutral
  double engine_rpm = 0.0;   // rpm
  double drive_power = 0.0;  // W      at the driven wheels
  double energy = 0.0;       // J      total energy of the whole scene
  Health health = Health::Ok;
};

// Reads vehicle v from the simulator's state and its last force evaluation.
// energy is filled only when with_energy (it costs one force-free pass, in
// the diagnostics' scratch: the simulator is not changed).
VehicleSample sampleVehicle(const Simulator& sim, int vehicle, bool with_energy);

}  // namespace groundsim
