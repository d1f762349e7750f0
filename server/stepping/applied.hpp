// A session's applied-command log (docs/logging.md, Re-simulation): every
// change of its simulation that does not follow from the scenario, at the
// tick it took effect, with the values applied. Published through
// Output::publishApplied (applied_t on the bus), and read back by the
// re-simulator (resimulate.hpp), which applies the same entries through the
// same functions below, so the session and its re-simulation cannot drift
// apart in what an entry means.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stepping/frame_build.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::stepping {

// Numbered as applied_t.KIND_*.
enum class AppliedKind : int { Drive = 1, Controls = 2, DriveTimeout = 3, ControlsTimeout = 4, Reset = 5,
                               Pause = 6, Resume = 7, Step = 8, SetMode = 9, Stop = 10, End = 11, Respawn = 12,
                               Refine = 13 };
const char* appliedKindName(AppliedKind k);

struct Applied {
  std::string session_id;
  std::int64_t seq = 0;        // per session, from 0
  std::int64_t frame_seq = 0;  // the frame published next
  std::int64_t tick = 0;       // the step from tick to tick + 1 is the first to feel it
  double t = 0.0;
  AppliedKind kind = AppliedKind::Drive;
  int vehicle = -1;
  std::vector<WheelControl> wheels;  // Drive: as applied
  CarControls controls;              // Controls: as applied
  std::int64_t steps = 0;            // Step; Refine: the integrator substeps per step from here on
  int mode = 0;                      // SetMode (0: unchanged)
  double rate = 0.0, publish_rate = 0.0;
  std::string reason;                // Stop, End
  std::int64_t epoch = 0;            // the owner's epoch (docs/fleet.md)
};

// What the session and the re-simulator both keep between entries.
struct DrivenCars {
  std::vector<bool> driven;  // per road car: a client took over from the control table
};

// Each entry's effect on the simulation (the only place it is written).
// wheels: the vehicle's wheels' global indices.
void applyDrive(Simulator& sim, const std::vector<int>& wheels, const std::vector<WheelControl>& applied);
void applyCarControls(Simulator& sim, DrivenCars& cars, int road_car, const CarControls& applied);
void releaseDrive(Simulator& sim);      // every wheel's drive and brake torque to zero
void releasePedals(Simulator& sim);     // every road car's throttle and brake to zero
// One vehicle's controls timed out (entries with `vehicle` >= 0): only its
// own wheels' torques, or its own road car's pedals, go to zero.
void releaseDrive(Simulator& sim, const std::vector<int>& wheels);
void releasePedals(Simulator& sim, int road_car);
// Whether a command holds something the controls timeout must release.
bool holdsTorque(const std::vector<WheelControl>& wheels);  // a drive or brake torque
bool holdsPedal(const CarControls& c);                      // throttle or brake
void resetTo(Simulator& sim, DrivenCars& cars, const State& initial);
// An entry of the log applied again to a simulation at its tick (the
// re-simulator, and a session resumed from a lost owner's log): its effect
// on the simulation, through the functions above; entries without one
// (pause, step, stop ...) do nothing here. Returns "" or why it cannot (a
// vehicle the scenario lacks).
// race: the session's race (race_glue.hpp), null without one: a reset
// restarts it, a respawn needs it.
struct RaceGlue;
std::string applyEntry(Simulator& sim, DrivenCars& cars, const std::vector<VehicleWheels>& vehicles,
                       const State& initial, const Applied& a, RaceGlue* race = nullptr);
// Before each step: the scenario's control-table rows due to cars no client drives.
void followControlTables(Simulator& sim, const DrivenCars& cars, const std::vector<scenario::ControlTable>& tables);

}  // namespace groundsim::stepping
