// Velocity Verlet (kick-drift-kick) and the helpers the integrators share.
#include "forces.hpp"
#include "integrators.hpp"
#include "road_car_phase.hpp"

namespace groundsim {

Quat rotateMidpoint(const Quat& q0, const Mat3& inv_inertia_body, const Vec3& L, double h) {
  const Mat3 R0 = q0.toRotationMatrix();
  Vec3 omega = R0 * (inv_inertia_body * (R0.transpose() * L));
  for (int pass = 0; pass < 2; ++pass) {
    const Mat3 Rm = integrateRotation(q0, omega, 0.5 * h).toRotationMatrix();
    omega = Rm * (inv_inertia_body * (Rm.transpose() * L));
  }
  return integrateRotation(q0, omega, h);
}

bool forcesDependOnStep(const Model& m, const std::vector<WheelControl>& applied, const Workspace& ws) {
  if (!m.road_cars.empty()) return true;  // velocity-level brakes, ABS and traction control
  if (m.opt.contact.friction_model == FrictionModel::StickSlip && m.opt.contact.friction > 0.0 &&
      ws.ncontacts > 0)
    return true;
  for (const auto& c : applied)
    if (c.brake_torque > 0.0) return true;
  return false;
}

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
  if (ws.ncontacts > 0 && (m.opt.contact.damping != 0.0 || m.opt.contact.friction != 0.0)) return false;
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

  const bool reuse = cache_valid_ && cache_y_.size() == s.y.size() &&
                     (cache_y_.array() == s.y.array()).all() && sameControls(cache_controls_, s.applied);
  double p0 = 0.0;  // drive power at the start (zero whenever the cache is used)
  if (reuse) {
    kick(m, s.y, cache_force_, cache_torque_, cache_particle_force_, half);
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
    q = rotateMidpoint(Quat(q), m.bodies[i].inv_inertia, bodyMom(s.y, i), h);
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

  cache_valid_ = velocityIndependent(m, s.applied, ws);
  if (cache_valid_) {
    // sized on the first use; same sizes afterwards, so no allocation
    cache_y_ = s.y;
    cache_controls_ = s.applied;
    cache_force_ = ws.body_force;
    cache_torque_ = ws.body_torque;
    cache_particle_force_ = ws.particle_force;
  }
}

}  // namespace groundsim
