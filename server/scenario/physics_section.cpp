#include <string>
#include <vector>

#include "physics/integrators/integrator.hpp"
#include "scenario/sections.hpp"

namespace groundsim::scenario {
namespace {

const std::vector<std::string> kIntegrators = {"semi_implicit_euler", "velocity_verlet", "rk4",
                                               "implicit_euler", "adaptive"};

IntegratorKind integratorKind(const std::string& s) {
  if (s == "velocity_verlet") return IntegratorKind::VelocityVerlet;
  if (s == "rk4") return IntegratorKind::Rk4;
  if (s == "implicit_euler") return IntegratorKind::ImplicitEuler;
  if (s == "adaptive") return IntegratorKind::Adaptive;
  return IntegratorKind::SemiImplicitEuler;
}

}  // namespace

void readPhysics(ObjectReader r, Options& opt) {
  const Options def;
  // whether the chosen integrator exists is checked by buildScene: it is a
  // property of this build, not of the document
  opt.integrator = integratorKind(r.choice("integrator", integratorName(def.integrator), kIntegrators));
  // dt beyond 0.1 s cannot resolve any contact of a 2000 N/m ground; below
  // 1 ns it resolves nothing a vehicle does, and duration / dt would be
  // beyond any step budget (1e-20 used to run 0 steps and report "ok")
  opt.dt = r.number("dt", def.dt, Range::closed(kMinDt, 0.1));
  opt.substeps = r.integer("substeps", def.substeps, 1, 10000);
  opt.tolerance = r.number("tolerance", def.tolerance, Range{0.0, 1.0, true, false});
  opt.gravity = r.vec3("gravity", def.gravity, Range::closed(-1000.0, 1000.0));
  opt.deterministic = r.boolean("deterministic", def.deterministic);
  ObjectReader limits = r.object("limits");
  opt.limits.max_penetration = limits.number("max_penetration", def.limits.max_penetration, Range::positive());
  opt.limits.max_speed = limits.number("max_speed", def.limits.max_speed, Range::positive());
  opt.limits.max_energy_growth = limits.number("max_energy_growth", def.limits.max_energy_growth, Range::positive());
  limits.finish();
  r.finish();
}

void readContact(ObjectReader r, ContactParams& c) {
  const ContactParams def;
  c.stiffness = r.number("stiffness", def.stiffness, Range::positive());
  c.damping = r.number("damping", def.damping, Range::nonNegative());
  c.damping_model = r.choice("damping_model", "kelvin_voigt", {"kelvin_voigt", "hunt_crossley"}) == "hunt_crossley"
                        ? NormalDamping::HuntCrossley
                        : NormalDamping::KelvinVoigt;
  c.friction = r.number("friction", def.friction, Range::nonNegative(100.0));
  const std::string fm = r.choice("friction_model", "stick_slip", {"stick_slip", "regularized", "sign"});
  c.friction_model = fm == "regularized" ? FrictionModel::Regularized
                     : fm == "sign"      ? FrictionModel::Sign
                                         : FrictionModel::StickSlip;
  c.slip_velocity = r.number("slip_velocity", def.slip_velocity, Range::positive());
  c.friction_iterations = r.integer("friction_iterations", def.friction_iterations, 1, 1000);
  r.finish();
}

}  // namespace groundsim::scenario
