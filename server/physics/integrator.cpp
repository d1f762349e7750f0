#include "integrator.hpp"

#include <stdexcept>

#include "integrators.hpp"

namespace groundsim {

void normalizeRotations(const Model& m, Eigen::VectorXd& y) {
  for (int i = 0; i < static_cast<int>(m.bodies.size()); ++i) bodyRot(y, i).normalize();
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
