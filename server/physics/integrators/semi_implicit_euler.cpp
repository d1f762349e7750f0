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
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    auto v = bodyVel(s.y, i);
    auto L = bodyMom(s.y, i);
    v += h * ws.body_force[i] / m.bodies[i].mass;  // (18)
    L += h * ws.body_torque[i];                     // (20)
    bodyPos(s.y, i) += h * v;                       // (19)
    // (21) and (11)-(12): rotate by the angular velocity at the half-step
    // orientation (implicit midpoint, two fixed-point passes). With the
    // inertia of the start of the step only, a free body's energy drifts and
    // its precession runs fast; the midpoint rule is symmetric and does not.
    // (one pass, from the start-of-step inertia the kinematics computed)
    auto q = bodyRot(s.y, i);
    const Quat q0(q);
    q = rotateMidpoint(q0, m.bodies[i].inv_inertia, ws.inv_inertia_world[i] * L, L, h, 1);
  }
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j) {
    const int o = particleOffset(nb, j);
    s.y.segment<3>(o + 3) += h * ws.particle_force[j] / m.particles[j].mass;
    s.y.segment<3>(o) += h * s.y.segment<3>(o + 3);
  }
  kickRoadCars(m, s.y, ws, h);
  driftRoadCars(m, s.y, ws, h);
}

}  // namespace groundsim
