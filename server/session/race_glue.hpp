// A session's race (server/race): what Session keeps of it. The glue's
// functions are Session members defined in race_glue.cpp, so session.cpp
// only calls them at its hooks (start of a step, end of a step, reset,
// respawn request).
#pragma once

#include <memory>
#include <vector>

#include "physics/simulator.hpp"
#include "race/race.hpp"

namespace groundsim::session {

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

}  // namespace groundsim::session
