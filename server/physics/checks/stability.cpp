#include "physics/checks/stability.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "physics/integrators/integrator.hpp"

namespace groundsim {
namespace {

double integratorLimit(IntegratorKind k, double zeta) {
  switch (k) {
    case IntegratorKind::SemiImplicitEuler:
    case IntegratorKind::VelocityVerlet:
      return 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta);
    case IntegratorKind::Rk4:
      return 2.83;
    case IntegratorKind::ImplicitEuler:
    case IntegratorKind::Adaptive:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

std::string nameOfPoint(const Model& m, int point) {
  const Point& p = m.points[point];
  if (p.body >= 0) return "'" + m.bodies[p.body].name + "'";
  return "particle " + std::to_string(p.particle);
}

double massOfPoint(const Model& m, int point) {
  const Point& p = m.points[point];
  return p.body >= 0 ? m.bodies[p.body].mass : m.particles[p.particle].mass;
}

StiffMode makeMode(const Model& m, std::string what, double k, double c, double mass) {
  StiffMode s;
  s.what = std::move(what);
  s.omega = std::sqrt(k / mass);
  s.zeta = c / (2.0 * std::sqrt(k * mass));
  s.limit = integratorLimit(m.opt.integrator, s.zeta);
  s.dt_limit = s.limit / s.omega;
  return s;
}

}  // namespace

std::vector<StiffMode> stiffestModes(const Model& m) {
  std::vector<StiffMode> out;
  const double h = m.opt.dt / std::max(1, m.opt.substeps);
  auto worse = [h](const StiffMode& a, const StiffMode& b) {
    return a.omega * h / a.limit > b.omega * h / b.limit;
  };
  // ground: the lightest body or particle that can touch it
  const ContactParams& cp = m.opt.contact;
  if (cp.stiffness > 0) {
    StiffMode best;
    bool any = false;
    for (int k : m.contact_points) {
      const int body = m.points[k].body;
      if (body >= 0 && m.bodies[body].ground_stiffness > 0.0) continue;  // an object: its own substeps
      const StiffMode s = makeMode(m, "ground contact of " + nameOfPoint(m, k), cp.stiffness,
                                   cp.damping_model == NormalDamping::KelvinVoigt ? cp.damping : 0.0,
                                   massOfPoint(m, k));
      if (!any || worse(s, best)) best = s;
      any = true;
    }
    for (const Wheel& w : m.wheels)
      if (w.contact == WheelContact::Circle) {
        const StiffMode s = makeMode(m, "ground contact of '" + m.bodies[w.body].name + "'", cp.stiffness,
                                     cp.damping, m.bodies[w.body].mass);
        if (!any || worse(s, best)) best = s;
        any = true;
      }
    if (any) out.push_back(best);
  }
  // everything pushing on one part at once: a wheel between the ground and
  // its bearing feels both stiffnesses and both dampers, and damping lowers
  // the symplectic limit (a damped ground made a 'fast' car take off)
  {
    std::map<std::string, std::pair<double, double>> total;  // k, c per part
    std::map<std::string, double> mass;
    for (int k : m.contact_points) {
      const std::string n = nameOfPoint(m, k);
      const int body = m.points[k].body;
      if (total.count(n) || (body >= 0 && m.bodies[body].ground_stiffness > 0.0)) continue;
      total[n] = {cp.stiffness, cp.damping_model == NormalDamping::KelvinVoigt ? cp.damping : 0.0};
      mass[n] = massOfPoint(m, k);
    }
    for (const Wheel& w : m.wheels)
      if (w.contact == WheelContact::Circle) {
        const std::string n = "'" + m.bodies[w.body].name + "'";
        total[n] = {cp.stiffness, cp.damping};
        mass[n] = m.bodies[w.body].mass;
      }
    for (const Spring& s : m.springs)
      for (int end : {s.a, s.b}) {
        const std::string n = nameOfPoint(m, end);
        if (nameOfPoint(m, s.a) == nameOfPoint(m, s.b)) break;
        total[n].first += s.stiffness;
        total[n].second += s.damping;
        mass[n] = massOfPoint(m, end);
      }
    bool found = false;
    StiffMode best;
    for (const auto& [n, kc] : total) {
      if (!(kc.first > 0)) continue;
      const StiffMode s = makeMode(m, "ground and springs on " + n, kc.first, kc.second, mass[n]);
      if (!found || worse(s, best)) best = s;
      found = true;
    }
    if (found) out.push_back(best);
  }
  // springs: parallel springs between the same two parts add up, and the
  // pair moves with its reduced mass
  std::map<std::pair<std::string, std::string>, std::pair<double, double>> pairs;  // k, c
  std::map<std::pair<std::string, std::string>, double> reduced;
  for (const Spring& s : m.springs) {
    auto key = std::make_pair(nameOfPoint(m, s.a), nameOfPoint(m, s.b));
    if (key.first == key.second) continue;  // within one rigid body: no mode
    pairs[key].first += s.stiffness;
    pairs[key].second += s.damping;
    const double ma = massOfPoint(m, s.a), mb = massOfPoint(m, s.b);
    reduced[key] = ma * mb / (ma + mb);
  }
  bool any = false;
  StiffMode best;
  for (const auto& [key, kc] : pairs) {
    if (!(kc.first > 0)) continue;
    const StiffMode s = makeMode(m, "springs between " + key.first + " and " + key.second, kc.first,
                                 kc.second, reduced[key]);
    if (!any || worse(s, best)) best = s;
    any = true;
  }
  if (any) out.push_back(best);
  return out;
}

std::vector<std::string> stabilityWarnings(const Model& m) {
  std::vector<std::string> out;
  const double h = m.opt.dt / std::max(1, m.opt.substeps);
  for (const StiffMode& s : stiffestModes(m)) {
    if (!std::isfinite(s.limit)) continue;
    const double ratio = s.omega * h / s.limit;
    if (ratio < kStabilityMargin) continue;
    std::ostringstream o;
    o.precision(3);
    o << "/physics/dt: " << h << " s is " << (ratio > 1 ? "beyond" : "near") << " the stability limit "
      << s.dt_limit << " s of " << integratorName(m.opt.integrator) << " for the " << s.what
      << " (omega = " << s.omega << " rad/s, damping ratio " << s.zeta << ", omega*dt must stay below "
      << s.limit << ")" << (ratio > 1 ? ": expect divergence" : ": expect poor accuracy");
    out.push_back(o.str());
  }
  // a vehicle the ground cannot hold up: its static sag, weight per wheel
  // over the penalty stiffness, runs into the penetration limit
  const double g = m.opt.gravity.norm(), S = m.opt.contact.stiffness;
  for (size_t v = 0; v < m.vehicle_body.size() && S > 0 && g > 0; ++v) {
    double mass = m.vehicle_body[v] >= 0 ? m.bodies[m.vehicle_body[v]].mass : 0.0;
    int wheels = 0;
    for (size_t w = 0; w < m.wheels.size(); ++w)
      if (m.vehicle_of_wheel[w] == static_cast<int>(v)) {
        mass += m.bodies[m.wheels[w].body].mass;
        ++wheels;
      }
    bool road_car = false;  // stands on its tyres' own vertical springs, not on the ground's
    for (const RoadCar& rc : m.road_cars) road_car |= rc.vehicle == static_cast<int>(v);
    if (road_car) continue;
    const double sag = mass * g / (std::max(wheels, 1) * S);
    if (sag < 0.5 * m.opt.limits.max_penetration) continue;
    std::ostringstream o;
    o.precision(3);
    o << "/contact/stiffness: " << S << " N/m lets vehicle '" << m.vehicle_names[v] << "' (" << mass
      << " kg) sink about " << sag << " m, against a penetration limit of " << m.opt.limits.max_penetration
      << " m: raise the stiffness to at least " << mass * g / (std::max(wheels, 1) * 0.1 * m.opt.limits.max_penetration)
      << " N/m (a tenth of the limit)";
    out.push_back(o.str());
  }
  return out;
}

}  // namespace groundsim
