// The step of a car on rim-point wheels (the report's ring car),
// specialised for what such a model holds: rigid bodies whose wheels are
// rims of contact points fanned out by springs to points of another body,
// a plane, stick-slip friction, semi-implicit Euler. Per rim, one loop
// over its points does the kinematics, both spring fans, the plane's H and
// the force and torque sums, so the points never go to memory; only the
// few points below the plane become contacts. No dynamic dispatch, no
// broad phase, the tangent basis computed once (the plane's normal is the
// same everywhere), no allocation.
//
// It runs only where the model does not ask for physics.deterministic: its
// sums run in another order than the general force loop's, so it gives
// other bits (round-off only; tests/physics/ring_car_test.cpp), and the
// deterministic promise (docs/performance.md) is kept by the general loop.
#pragma once

#include <memory>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

// nullptr when the model can take the ring-car step; otherwise why not.
const char* ringCarUnsupported(const Model& m);

// One car's ring-car step, owned by its Simulator.
class RingCar {
 public:
  explicit RingCar(const Model& m);  // requires ringCarUnsupported(m) == nullptr
  ~RingCar();
  RingCar(const RingCar&) = delete;
  RingCar& operator=(const RingCar&) = delete;
  // One step of opt.dt (opt.substeps integrator steps), with the applied
  // controls in s.applied: what Simulator::step does between applyControls
  // and checkHealth. Sets what the health check reads (ws.max_depth) and
  // ws.friction_sweeps; the rest of the workspace waits for exportTo.
  void step(const Model& m, State& s, Workspace& ws);
  // Fills the workspace as the general force loop leaves it: it runs that
  // loop (computeForces) on the configuration and controls of the last
  // evaluation. Called on demand (Simulator::workspace).
  void exportTo(const Model& m, Workspace& ws) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace groundsim
