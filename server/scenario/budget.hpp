// The model budget: limits on what one scenario may ask for, checked while
// it is validated, before anything is built, so that a small hostile text
// can cost neither gigabytes nor hours. Each limit is refused with the JSON
// path, the count asked for and the limit, naming the flag that raises it:
//   /vehicles: 50000 vehicles, at most 64 (groundsim run --max-vehicles)
// The counts are estimated from the validated specs (estimateModelSize),
// not by building: the estimate is exact for the shipped vehicle builders
// (tests/scenario/budget_test.cpp compares it with built models).
// docs/reliability.md lists the limits and their defaults.
#pragma once

#include <cstddef>
#include <string>

namespace groundsim::scenario {

struct Budget {
  // Who sets the limits: named in every refusal with the limit's flag,
  // "(groundsim run --max-vehicles)". The server sets "server".
  std::string source = "groundsim run";

  // the text, checked before a JSON tree is built
  std::size_t max_document_bytes = 8u << 20;  // --max-document-bytes
  int max_depth = 64;                         // --max-depth     nesting of objects and arrays
  std::size_t max_json_values = 1000000;      // --max-json-values  values (scalars, objects, arrays)
  std::size_t max_expression_length = 4096;   // --max-expression-length  characters of ground.expression

  // the model, estimated from the specs before building
  int max_vehicles = 64;                      // --max-vehicles
  long long max_points = 200000;              // --max-points    mass and attachment points
  long long max_springs = 400000;             // --max-springs
  long long max_particles = 100000;           // --max-particles free point masses (deformable rims)
  long long max_state = 1000000;              // --max-state     doubles in the state vector
  // implicit_euler factors a dense (state x state) matrix every step (three
  // such matrices are kept): 2000 is 96 MB
  long long max_implicit_state = 2000;        // --max-implicit-state

  // the run: integrator steps over the duration (duration / dt * substeps)
  // and the work they cost (steps times an estimate of one step's cost in
  // point/spring evaluations, see ModelSize::work_per_step)
  double max_steps = 1e9;                     // --max-steps
  double max_work = 1e12;                     // --max-work

  // "(groundsim run --max-vehicles)"
  std::string flag(const char* name) const { return "(" + source + " --" + name + ")"; }
};

// What a validated scenario will build, counted from its specs.
struct ModelSize {
  long long vehicles = 0, bodies = 0, points = 0, particles = 0, springs = 0, contact_points = 0;
  long long state = 0;            // 13 per body + 6 per particle + 20 per road car
  double steps = 0.0;             // integrator steps over the scenario's duration
  // derivative evaluations per step x (points + springs + contact points),
  // + state^3 / 3 for implicit_euler's LU factorisation
  double work_per_step = 0.0;
};

}  // namespace groundsim::scenario
