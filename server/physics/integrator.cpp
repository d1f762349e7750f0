#include "integrator.hpp"

#include <stdexcept>

#include "integrator_methods.hpp"

namespace groundsim {

void normalizeRotations(const Model& m, Eigen::VectorXd& y) {
  for (int i = 0; i < static_cast<int>(m.bodies.size()); ++i) bodyRot(y, i).normalize();
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

bool forcesDependOnStep(const Model& m, const std::vector<WheelControl>& applied, const Workspace& ws) {
  if (!m.road_cars.empty()) return true;  // velocity-level brakes, ABS and traction control
  if (m.opt.contact.friction_model == FrictionModel::StickSlip && m.opt.contact.friction > 0.0 &&
      ws.ncontacts > 0)
    return true;
  for (const auto& c : applied)
    if (c.brake_torque > 0.0) return true;
  return false;
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
