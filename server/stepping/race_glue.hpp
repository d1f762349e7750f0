// A session's race (server/race): what Session keeps of it, and what a
// race does to the simulation at its hooks (start of a step, end of a step,
// reset, respawn). The free functions below are that effect, used alike by
// the session (its members in race_glue.cpp add the events) and by the
// re-simulator (resimulate.hpp), so that a recorded race re-simulates bit
// for bit: the countdown's hold, the brakes off at go, respawns (an applied
// entry, placed again by the same rule) and their protection.
#pragma once

#include <memory>
#include <vector>

#include "physics/simulator.hpp"
#include "race/race.hpp"

namespace groundsim::stepping {

struct RaceGlue {
  race::Race race;
  std::vector<race::Vec2> before, after;  // body centres at the start and end of the step
  bool announced = false;                 // the layout and countdown were published
  // Respawn protection: a respawned car passes through the other cars and
  // objects until ghost_until[car] (simulated s). The session then steps a
  // copy of its model in which those cars' collision groups are empty
  // (ghostModel); `model` is the scenario's, stepped again once none is.
  std::shared_ptr<const Model> model;
  std::vector<double> ghost_until;
  bool ghosted = false;                   // the session steps a ghost model now
  RaceGlue(scenario::RaceSpec spec, int cars, std::shared_ptr<const Model> m)
      : race(std::move(spec), cars), model(std::move(m)), ghost_until(static_cast<std::size_t>(cars), 0.0) {}
};

// The race of a session's scenario document, or null when it has none.
std::unique_ptr<RaceGlue> makeRaceGlue(const std::string& scenario_json, std::shared_ptr<const Model> m);

// A copy of `m` in which the collision groups of the vehicles with
// ghost[v] set hold no probes and no shapes: those vehicles touch the
// ground only.
std::shared_ptr<const Model> ghostModel(const Model& m, const std::vector<bool>& ghost);

// Moves vehicle v of `initial`'s pose (its chassis, wheels and rim points)
// to (x, y) on the ground with heading yaw, at rest, into sim's state: the
// car as it stood on its grid slot, turned and carried there. The energy
// check's reference moves with it (a car put higher is no divergence).
void placeVehicle(Simulator& sim, const State& initial, int v, double x, double y, double yaw);

// Before a step: the cars' centres; during the countdown no throttle and
// the brakes on, whatever a driver sent.
void raceHold(RaceGlue& g, Simulator& sim);
// After the step from t0: protections that ended, the race's happenings
// (gates, laps, ...), and at go the brakes the countdown held come off.
std::vector<race::RaceEvent> raceStepped(RaceGlue& g, Simulator& sim, double t0);
// A reset: the race from its start, no car protected.
void raceRestart(RaceGlue& g, Simulator& sim);
// Car `car` put back upright at rest at its last gate (else its grid slot,
// else where it started), on the first spot along the gate line clear of
// the other cars, its pedals released; its protection begins. Returns the
// race's happenings (the respawn event).
std::vector<race::RaceEvent> raceRespawnCar(RaceGlue& g, Simulator& sim, const State& initial, int car);
// The model stepped: the scenario's, or a copy with protected cars as
// ghosts (a new Simulator on the same state: hits under way are dropped).
void raceGhosts(RaceGlue& g, Simulator& sim);
// The race's progress and its protections (JSON) for a session's
// snapshot, and back in a standby that resumes the session (then the
// protected cars are ghosts again): laps, gates and best laps survive a
// failover. raceRestore returns "" or why not.
nlohmann::json raceProgress(const RaceGlue& g);
std::string raceRestore(RaceGlue& g, Simulator& sim, const nlohmann::json& progress);

}  // namespace groundsim::stepping
