// One cell of the accuracy/cost sweep: a setting (integrator, step or
// tolerance, wheel fidelity) run on one scene, and what it measured.
#pragma once

#include <string>

#include "physics/simulator.hpp"
#include "physics/build/vehicle.hpp"

namespace groundsim::accuracy {

// Wheel model of the report's car: a ring of n rim points on rim springs, or
// the exact circle contact with a bearing coupling.
enum class Fidelity { Rim20, Rim40, Rim80, Rim160, Circle };
const char* fidelityName(Fidelity f);
CarParams carParams(Fidelity f);

struct Setting {
  IntegratorKind integrator = IntegratorKind::SemiImplicitEuler;
  double dt = 1e-4;          // s   step (output step for adaptive)
  double tolerance = 1e-6;   // -   adaptive only
  Fidelity fidelity = Fidelity::Rim20;
  Options apply(Options o) const;  // o with this setting's integrator and step
  std::string label() const;       // "rk4 dt=1e-4" / "adaptive tol=1e-6"
};

struct Result {
  std::string scene;
  Setting setting;
  bool uses_fidelity = true;  // false: the scene has no wheels
  bool healthy = true;
  std::string status = "ok";  // health name when diverged
  double value = 0.0;         // measured quantity
  double expected = 0.0;      // analytic or reference answer
  double error = 0.0;         // relative (or absolute, see error_unit)
  const char* error_unit = "rel";  // "rel" or "m"
  double sim_seconds = 0.0;
  double wall_seconds = 0.0;
  long long evaluations = 0;
  double simPerWall() const { return wall_seconds > 0 ? sim_seconds / wall_seconds : 0.0; }
  double evalsPerSim() const { return sim_seconds > 0 ? evaluations / sim_seconds : 0.0; }
};

// Steps sim to time t (a whole number of steps), timing the work into r.
// False if the run diverged (r.healthy, r.status set).
bool runTo(Simulator& sim, double t, Result& r);

}  // namespace groundsim::accuracy
