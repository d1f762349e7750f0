#include "physics/integrators/integrator.hpp"

#include <stdexcept>

#include "physics/forces/forces.hpp"
#include "physics/integrators/integrator_methods.hpp"

namespace groundsim {

void normalizeRotations(const Model& m, Eigen::VectorXd& y) {
  for (int i = 0; i < static_cast<int>(m.bodies.size()); ++i) bodyRot(y, i).normalize();
}

void semiImplicitBodyUpdate(const Model& m, Eigen::VectorXd& y, int i, const Vec3& dv, const Vec3& dL,
                            const Mat3& inv_inertia_world, double h) {
  auto v = bodyVel(y, i);
  auto L = bodyMom(y, i);
  v += dv;
  L += dL;
  bodyPos(y, i) += h * v;
  auto q = bodyRot(y, i);
  const Quat q0(q);
  q = rotateMidpoint(q0, m.bodies[i].inv_inertia, inv_inertia_world * L, L, h, 1);
}

void semiImplicitBodiesAndParticles(const Model& m, Eigen::VectorXd& y, const Workspace& ws, double h,
                                    const unsigned char* skip) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i)
    if (!skip || !skip[i])
      semiImplicitBodyUpdate(m, y, i, h * ws.body_force[i] / m.bodies[i].mass, h * ws.body_torque[i],
                             ws.inv_inertia_world[i], h);
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j) {
    const int o = particleOffset(nb, j);
    y.segment<3>(o + 3) += h * ws.particle_force[j] / m.particles[j].mass;
    y.segment<3>(o) += h * y.segment<3>(o + 3);
  }
}

Vec3 angularVelocityAt(const Quat& q, const Mat3& inv_inertia_body, const Vec3& L) {
  const Mat3 R = q.toRotationMatrix();
  return R * (inv_inertia_body * (R.transpose() * L));
}

Quat rotateMidpoint(const Quat& q0, const Mat3& inv_inertia_body, const Vec3& omega0, const Vec3& L,
                    double h, int passes) {
  Vec3 omega = omega0;
  for (int pass = 0; pass < passes; ++pass) {
    const Mat3 Rm = integrateRotation(q0, omega, 0.5 * h).toRotationMatrix();
    omega = Rm * (inv_inertia_body * (Rm.transpose() * L));
  }
  return integrateRotation(q0, omega, h);
}

bool contactsHaveFriction(const Workspace& ws) {
  for (int i = 0; i < ws.ncontacts; ++i)
    if (ws.contacts[static_cast<size_t>(i)].mu > 0.0) return true;
  return false;
}

bool forcesDependOnStep(const Model& m, const std::vector<WheelControl>& applied, const Workspace& ws) {
  if (!m.road_cars.empty()) return true;  // velocity-level brakes, ABS and traction control
  // each contact's own mu: friction by place can grip where the scene's
  // contact.friction is 0
  if (m.opt.contact.friction_model == FrictionModel::StickSlip && contactsHaveFriction(ws)) return true;
  if (!velocityLevelBrakes(m)) return false;
  for (const auto& c : applied)
    if (c.brake_torque > 0.0) return true;
  return false;
}

const char* integratorFrictionConflict(IntegratorKind kind, FrictionModel friction) {
  const bool ode = kind == IntegratorKind::Rk4 || kind == IntegratorKind::Adaptive ||
                   kind == IntegratorKind::ImplicitEuler;
  if (!ode || friction == FrictionModel::Regularized) return nullptr;
  if (friction == FrictionModel::StickSlip)
    return "stick_slip is a velocity-level solve sized by the step, which only semi_implicit_euler and "
           "velocity_verlet own; this integrator needs \"regularized\" (smooth Coulomb friction, "
           "regularisation velocity contact.slip_velocity) to reach its order";
  return "sign friction is discontinuous at zero slip, so this integrator cannot reach its order; use "
         "\"regularized\" (smooth Coulomb friction, regularisation velocity contact.slip_velocity)";
}

const char* integratorName(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::SemiImplicitEuler: return "semi_implicit_euler";
    case IntegratorKind::VelocityVerlet: return "velocity_verlet";
    case IntegratorKind::Rk4: return "rk4";
    case IntegratorKind::ImplicitEuler: return "implicit_euler";
    case IntegratorKind::Adaptive: return "adaptive";
  }
  return "?";
}

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::SemiImplicitEuler: return std::make_unique<SemiImplicitEuler>();
    case IntegratorKind::VelocityVerlet: return std::make_unique<VelocityVerlet>();
    case IntegratorKind::Rk4: return std::make_unique<Rk4>();
    case IntegratorKind::ImplicitEuler: return std::make_unique<ImplicitEuler>();
    case IntegratorKind::Adaptive: return std::make_unique<Adaptive>();
  }
  throw std::invalid_argument(std::string("integrator not available: ") + integratorName(kind));
}

}  // namespace groundsim
