// The sedan's manoeuvres in the sweep (issue 9, "the trade, where it
// matters"): configs/sedan.json and configs/sedan_hills.json built through
// the scenario layer, as `groundsim run` builds them, with the setting's
// integrator and step. Each run records the body's path (centre of mass
// every 16 ms, a whole number of steps at every step in the grid) and one key
// figure; the sweep compares both with a converged reference run.
#pragma once

#include <string>
#include <vector>

#include "cell.hpp"
#include "physics/base/math.hpp"

namespace groundsim::accuracy {

struct RoadManoeuvre {
  std::string name;
  std::string what;      // docs: the manoeuvre
  std::string key;       // docs: the key figure and its unit
  double duration = 0;   // s
};

// step_steer, lane_change, braking, hill_road, bumps
const std::vector<RoadManoeuvre>& roadManoeuvres();

struct RoadRun {
  std::string manoeuvre;
  Setting setting;       // fidelity unused
  bool stick_slip = false;  // tyres.model "stick_slip" instead of the Magic Formula
  bool healthy = true;
  std::string status = "ok";
  std::vector<Vec3> path;  // centre of mass at t = 16 ms, 32 ms, ...
  double key = 0;          // the key figure
  double length = 0;       // m  path length (the reference's sets the scale)
  // filled against the reference
  double path_rms = 0, path_max = 0;  // relative to the reference's length
  double key_error = 0;               // relative
  double sim_seconds = 0, wall_seconds = 0;
  long long evaluations = 0;
  double simPerWall() const { return wall_seconds > 0 ? sim_seconds / wall_seconds : 0.0; }
  double evalsPerSim() const { return sim_seconds > 0 ? evaluations / sim_seconds : 0.0; }
};

// Runs one manoeuvre at one setting (configs read from `configs`), with
// the sedan's Magic Formula tyres or the stick-slip tyre.
RoadRun runRoad(const RoadManoeuvre& m, const Setting& s, const std::string& configs, bool stick_slip = false);

// Fills r's errors against ref (path samples compared where both exist; a
// shorter healthy path cannot happen, a diverged run keeps no errors).
void compareRoad(RoadRun& r, const RoadRun& ref);

// The step grid of the sweep (s) and the reference: RK4 at kRoadRefDt, its
// convergence measured against RK4 at 2 kRoadRefDt.
std::vector<Setting> roadSettings(bool quick);
// The stick-slip tyre's grid: the integrators that take it (semi-implicit
// Euler, velocity Verlet), and its own reference: Verlet (no RK4: it is
// refused with the stick-slip tyre) at kStickRefDt, its convergence
// measured against Verlet at 2 kStickRefDt.
std::vector<Setting> stickSlipSettings(bool quick);
inline constexpr double kStickRefDt = 6.25e-5;
inline constexpr double kRoadRefDt = 1.25e-4;
inline constexpr double kRoadSample = 0.016;

}  // namespace groundsim::accuracy
