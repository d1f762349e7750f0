#include "cell.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "physics/integrators/integrator.hpp"

namespace groundsim::accuracy {

const char* fidelityName(Fidelity f) {
  switch (f) {
    case Fidelity::Rim20: return "rim20";
    case Fidelity::Rim40: return "rim40";
    case Fidelity::Rim80: return "rim80";
    case Fidelity::Rim160: return "rim160";
    case Fidelity::Circle: return "circle";
  }
  return "?";
}

CarParams carParams(Fidelity f) {
  CarParams p;
  switch (f) {
    case Fidelity::Rim20: p.rim_points = 20; break;
    case Fidelity::Rim40: p.rim_points = 40; break;
    case Fidelity::Rim80: p.rim_points = 80; break;
    case Fidelity::Rim160: p.rim_points = 160; break;
    case Fidelity::Circle:
      p.wheel_contact = WheelContact::Circle;
      p.coupling = WheelCoupling::Bearing;
      break;
  }
  return p;
}

Options Setting::apply(Options o) const {
  o.integrator = integrator;
  o.dt = dt;
  o.tolerance = tolerance;
  // what a scenario can ask for: the ODE integrators are refused with
  // stick-slip or sign friction (integratorFrictionConflict), so their cells
  // run with the smooth friction they need
  if (integratorFrictionConflict(integrator, o.contact.friction_model))
    o.contact.friction_model = FrictionModel::Regularized;
  return o;
}

std::string Setting::label() const {
  char buf[96];
  if (integrator == IntegratorKind::Adaptive)
    std::snprintf(buf, sizeof buf, "%s tol=%.0e", integratorName(integrator), tolerance);
  else
    std::snprintf(buf, sizeof buf, "%s dt=%.0e", integratorName(integrator), dt);
  // one digit unless it hides the step (2.5e-4 is not "2e-04")
  if (integrator != IntegratorKind::Adaptive && std::abs(std::strtod(std::strchr(buf, '=') + 1, nullptr) - dt) > 1e-9 * dt)
    std::snprintf(buf, sizeof buf, "%s dt=%.1e", integratorName(integrator), dt);
  return buf;
}

bool runTo(Simulator& sim, double t, Result& r) {
  const double dt = sim.model().opt.dt;
  const long long n = std::llround((t - sim.state().t) / dt);
  const long long e0 = sim.forceEvaluations();
  const double t0 = sim.state().t;
  const auto start = std::chrono::steady_clock::now();
  const bool ok = n <= 0 || sim.step(n);
  r.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.evaluations += sim.forceEvaluations() - e0;
  r.sim_seconds += sim.state().t - t0;
  if (!ok) {
    r.healthy = false;
    r.status = healthName(sim.state().health);
  }
  return ok;
}

}  // namespace groundsim::accuracy
