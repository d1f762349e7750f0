// The classical driver on a scenario's race, stepped in process: the
// baseline's lap times (bench/drivers, docs/drivers.md) and its checks.
#pragma once

#include <string>
#include <vector>

#include "drivers/classical_driver.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::drivers {

// What the driver senses of road car `car` (its body's pose and forward speed).
CarSense senseCar(const Model& m, const State& s, int car);

// The driver's car as the model has it: wheelbase and steering lock.
CarGeometry carGeometry(const Model& m, int car);

// Friction along the line: the ground's mu at each sample (its patches and
// friction map, else the scene's contact.friction).
std::vector<double> frictionAlong(const Model& m, const TrackLine& line);

struct LapRun {
  std::vector<double> laps;     // s, each completed lap (a stage: its one run)
  double race_time = 0.0;       // s since go when it finished, 0: did not
  int off_track = 0;            // times it left the track
  double worst_offset = 0.0;    // m, farthest from the driver's line once past the start line
  double profile_lap = 0.0;     // s, the speed profile's own lap (a flying lap)
  double line_length = 0.0;     // m
  bool healthy = true;
  std::string why;              // when not healthy: the simulation's reason
};

struct LapSetup {
  CarLimits limits;             // at friction 1 (frictionAlong scales them)
  DriverTuning tuning;
  double control_period = 0.02; // s   the driver acts at 50 Hz
  double time_limit = 600.0;    // s   simulated, after go
};

// Vehicle 0 of `scene` (built from `scenario`, which has a race) driven by
// the classical driver until it finishes or time_limit passes; the other
// vehicles stand braked on the grid.
LapRun runClassical(const scenario::Scenario& scenario, const scenario::Scene& scene, const LapSetup& setup);

}  // namespace groundsim::drivers
