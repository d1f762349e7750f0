// The classical driver on a scenario's race, stepped in process: the
// baseline's lap times (bench/drivers, docs/drivers.md) and its checks.
#pragma once

#include <string>
#include <vector>

#include "drivers/classical_driver.hpp"
#include "drivers/driver.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::drivers {

// What the driver senses of road car `car` (its body's pose and forward speed).
CarSense senseCar(const Model& m, const State& s, int car);

// The driver's car as the model has it: wheelbase and steering lock.
CarGeometry carGeometry(const Model& m, int car);

// The classical driver at the wheel of road car `road_car`, sensing it with
// senseCar (a session's bots, runClassical).
class ClassicalBot : public Driver {
 public:
  ClassicalBot(const TrackLine& line, const SpeedProfile& profile, const Model& m, int road_car,
               const DriverTuning& tuning = {})
      : driver_(line, profile, carGeometry(m, road_car), tuning), road_car_(road_car) {}
  Pedals drive(const Model& m, const State& s) override { return driver_.drive(senseCar(m, s, road_car_)); }
  void relocate() override { driver_.relocate(); }

 private:
  ClassicalDriver driver_;
  int road_car_ = 0;
};

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

// The same with any driver of vehicle 0, acting every `control_period` s
// (worst_offset measured from the race's driving line, profile_lap 0).
LapRun runDriver(const scenario::Scenario& scenario, const scenario::Scene& scene, Driver& driver,
                 double control_period, double time_limit);

}  // namespace groundsim::drivers
