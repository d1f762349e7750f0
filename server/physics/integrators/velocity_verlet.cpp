// Velocity Verlet (kick-drift-kick).
//
// The end-of-step forces become the next step's start forces when they
// cannot depend on velocity or on the step (no damping, friction, brakes or
// drive) and the state and controls are still the ones they were evaluated
// at: then reusing them gives the same bits as recomputing, so save/restore
// stays bit-exact. The cache lives in the Workspace (ws.verlet).
#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"
#include "physics/forces/road_car_phase.hpp"

namespace groundsim {

namespace {

// Whether the last evaluation in ws would give the same bits at any velocity
// and any step: nothing in it reads a velocity (dashpots, ground damping,
// friction, brakes) and no drive power is booked.
bool velocityIndependent(const Model& m, const std::vector<WheelControl>& applied, const Workspace& ws) {
  if (!m.road_cars.empty()) return false;
  for (const auto& c : applied)
    if (c.brake_torque != 0.0 || c.drive_torque != 0.0) return false;
  for (const Spring& sp : m.springs)
    if (sp.damping != 0.0) return false;
  if (ws.ncontacts > 0 && (m.opt.contact.damping != 0.0 || contactsHaveFriction(ws))) return false;
  return true;
}

bool sameControls(const std::vector<WheelControl>& a, const std::vector<WheelControl>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].drive_torque != b[i].drive_torque || a[i].brake_torque != b[i].brake_torque ||
        a[i].steer != b[i].steer)
      return false;
  return true;
}

// v += k F / m and L += k tau for every body and particle.
void kick(const Model& m, Eigen::VectorXd& y, const std::vector<Vec3>& force,
          const std::vector<Vec3>& torque, const std::vector<Vec3>& particle_force, double k) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    bodyVel(y, i) += k * force[i] / m.bodies[i].mass;
    bodyMom(y, i) += k * torque[i];
  }
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j)
    y.segment<3>(particleOffset(nb, j) + 3) += k * particle_force[j] / m.particles[j].mass;
}

}  // namespace

void VelocityVerlet::advance(const Model& m, State& s, Workspace& ws, double h) {
  const int nb = static_cast<int>(m.bodies.size());
  const int np = static_cast<int>(m.particles.size());
  const double half = 0.5 * h;

  Workspace::VerletCache& cache = ws.verlet;
  const bool reuse = cache.valid && cache.y.size() == s.y.size() &&
                     (cache.y.array() == s.y.array()).all() && sameControls(cache.controls, s.applied);
  double p0 = 0.0;  // drive power at the start (zero whenever the cache is used)
  if (reuse) {
    kick(m, s.y, cache.force, cache.torque, cache.particle_force, half);
  } else {
    computeForces(m, s.y, s.applied, half, ws);
    ++evaluations;
    p0 = ws.drive_power;
    kick(m, s.y, ws.body_force, ws.body_torque, ws.particle_force, half);
  }
  kickRoadCars(m, s.y, ws, half);  // never cached: a road car's forces read velocities
  driftRoadCars(m, s.y, ws, h);
  // drift with the half-step momenta
  for (int i = 0; i < nb; ++i) {
    bodyPos(s.y, i) += h * bodyVel(s.y, i);
    auto q = bodyRot(s.y, i);
    const Quat q0(q);
    const Vec3 L = bodyMom(s.y, i);
    q = rotateMidpoint(q0, m.bodies[i].inv_inertia, angularVelocityAt(q0, m.bodies[i].inv_inertia, L), L, h, 2);
  }
  for (int j = 0; j < np; ++j) {
    const int o = particleOffset(nb, j);
    s.y.segment<3>(o) += h * s.y.segment<3>(o + 3);
  }
  computeForces(m, s.y, s.applied, half, ws);
  ++evaluations;
  kick(m, s.y, ws.body_force, ws.body_torque, ws.particle_force, half);
  kickRoadCars(m, s.y, ws, half);
  s.drive_work += half * (p0 + ws.drive_power);

  cache.valid = velocityIndependent(m, s.applied, ws);
  if (cache.valid) {
    // sized by the Workspace: no allocation
    cache.y = s.y;
    cache.controls = s.applied;
    cache.force = ws.body_force;
    cache.torque = ws.body_torque;
    cache.particle_force = ws.particle_force;
  }
}

}  // namespace groundsim
