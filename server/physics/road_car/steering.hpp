// Ackermann steering and the powertrain's pure functions (steering.cpp,
// powertrain.cpp).
#pragma once

#include "physics/road_car/road_car.hpp"

namespace groundsim {

// Road-wheel angles (left, right) whose mean is delta, split so that with
// ackermann = 1 both wheel axes meet on the rear axle line:
// cot(delta_out) - cot(delta_in) = track / wheelbase. Closed form: with
// d = (delta_left - delta_right) / 2 and k = track / (2 wheelbase),
// sin 2d - k cos 2d = -k cos 2 delta.
void ackermannAngles(const SteeringParams& s, double wheelbase, double track, double delta, double* left,
                     double* right);

// Full-throttle engine torque at engine speed omega (rad/s), linear in the table, 0 above redline.
double engineTorque(const PowertrainParams& p, double omega);
// Total gear ratio (gearbox times final drive) of gear g (1..n, -1 reverse, 0 neutral).
double gearRatio(const PowertrainParams& p, int g);

struct DriveOut {
  double wheel_torque = 0.0;  // N m   total at the driven wheels (after efficiency)
  double engine_omega = 0.0;  // rad/s
};
// Engine (or motor) and gearbox at throttle, with the driven wheels turning
// at mean speed omega_wheels (rad/s). Below idle the clutch slips at the
// launch speed and passes the engine's torque there.
DriveOut driveTorque(const PowertrainParams& p, int gear, double throttle, double omega_wheels);

// The automatic gearbox's choice at full throttle: the gear giving the most
// wheel torque at this wheel speed within idle..redline (the top of the
// power curve); at part throttle the highest gear keeping the engine above
// a throttle-dependent speed.
int automaticGear(const PowertrainParams& p, double throttle, double omega_wheels);

}  // namespace groundsim
