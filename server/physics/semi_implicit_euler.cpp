// The report's integrator (section 4): forces at the current configuration,
// then momenta first and positions with the new velocities (eqs. 18-21),
// rotating each body by Rodrigues' formula with its new angular velocity.
// Symplectic for conservative forces; stable for omega h < 2.
#include "forces.hpp"
#include "integrators.hpp"
#include "road_car_phase.hpp"

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
    auto q = bodyRot(s.y, i);
    const Quat q0(q);
    const Mat3& Ib_inv = m.bodies[i].inv_inertia;
    Vec3 omega = ws.inv_inertia_world[i] * L;
    for (int pass = 0; pass < 1; ++pass) {
      const Mat3 Rm = integrateRotation(q0, omega, 0.5 * h).toRotationMatrix();
      omega = Rm * (Ib_inv * (Rm.transpose() * L));
    }
    q = integrateRotation(q0, omega, h);
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
