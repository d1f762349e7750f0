// The report's integrator (section 4): forces at the current configuration,
// then momenta first and positions with the new velocities (eqs. 18-21),
// rotating each body by Rodrigues' formula with its new angular velocity.
// Symplectic for conservative forces; stable for omega h < 2.
#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"
#include "physics/forces/road_car_phase.hpp"

namespace groundsim {

void SemiImplicitEuler::advance(const Model& m, State& s, Workspace& ws, double h) {
  computeForces(m, s.y, s.applied, h, ws);
  ++evaluations;
  s.drive_work += h * ws.drive_power;
  // (18) and (20), then (19), (21) and (11)-(12): rotate by the angular
  // velocity at the half-step orientation (implicit midpoint, one
  // fixed-point pass from the start-of-step inertia the kinematics
  // computed). With the inertia of the start of the step only, a free
  // body's energy drifts and its precession runs fast; the midpoint rule
  // is symmetric and does not.
  semiImplicitBodiesAndParticles(m, s.y, ws, h);
  kickRoadCars(m, s.y, ws, h);
  driftRoadCars(m, s.y, ws, h);
}

}  // namespace groundsim
