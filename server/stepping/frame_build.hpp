// A frame's physics from a simulator: what Session publishes and what the
// re-simulator (resimulate.hpp) compares with a recording, built by the
// same code so that the two agree to the bit.
#pragma once

#include <vector>

#include "physics/simulator.hpp"
#include "stepping/types.hpp"

namespace groundsim::stepping {

// Per vehicle: its wheels' global indices (telemetry order) and steering limits.
struct VehicleWheels {
  std::vector<int> wheels;
  std::vector<double> max_steer;      // 0 for wheels that do not steer
  int road_car = -1;                  // its index among the model's road cars, -1: not a road car
  int gears = 0;                      // a road car's forward gears (manual requests 1..gears)
};

std::vector<VehicleWheels> vehicleWheels(const Model& m);

// Fills t, tick, health, vehicles (sanitized: a diverged simulator's
// workspace may hold NaN), cars, contacts, objects, hits, model and energy.
void fillFrame(Frame& f, const Simulator& sim, const std::vector<VehicleWheels>& vehicles);

}  // namespace groundsim::stepping
