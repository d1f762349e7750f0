#include "physics/checks/diagnostics.hpp"

#include <cmath>
#include <cstring>
#include <sstream>

#include "physics/forces/body_contact.hpp"
#include "physics/forces/forces.hpp"

namespace groundsim {

const char* healthName(Health h) {
  switch (h) {
    case Health::Ok: return "ok";
    case Health::NonFinite: return "non_finite";
    case Health::Penetration: return "penetration";
    case Health::Speed: return "speed";
    case Health::Energy: return "energy";
  }
  return "?";
}

Energy computeEnergy(const Model& m, const State& s, Workspace& ws) {
  computeKinematics(m, s.y, s.applied, ws);
  detectGroundContacts(m, ws);
  bodyContacts(m, false, ws);
  Energy e;
  e.contact = ws.body_contact_energy;
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    const Body& b = m.bodies[i];
    const Vec3 v = bodyVel(s.y, i);
    e.kinetic += 0.5 * b.mass * v.squaredNorm() + 0.5 * ws.omega[i].dot(bodyMom(s.y, i));
    e.gravity -= b.mass * m.opt.gravity.dot(bodyPos(s.y, i));
  }
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j) {
    const int o = particleOffset(nb, j);
    e.kinetic += 0.5 * m.particles[j].mass * s.y.segment<3>(o + 3).squaredNorm();
    e.gravity -= m.particles[j].mass * m.opt.gravity.dot(s.y.segment<3>(o));
  }
  for (const Spring& sp : m.springs) {
    const Vec3 d = ws.pointPos(sp.b) - ws.pointPos(sp.a);
    const double stretch = sp.isotropic ? d.norm() : d.norm() - sp.rest_length;
    e.spring += 0.5 * sp.stiffness * stretch * stretch;
  }
  for (int c = 0; c < ws.ncontacts; ++c)
    e.ground += 0.5 * groundStiffness(m, ws.contacts[c].body) * ws.contacts[c].depth * ws.contacts[c].depth;
  return e;
}

Vec3 angularVelocity(const Model& m, const State& s, int body) {
  const Mat3 R = Quat(bodyRot(s.y, body)).normalized().toRotationMatrix();
  return R * (m.bodies[body].inv_inertia * (R.transpose() * bodyMom(s.y, body)));
}

Vec3 linearMomentum(const Model& m, const State& s) {
  Vec3 p = Vec3::Zero();
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) p += m.bodies[i].mass * bodyVel(s.y, i);
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j)
    p += m.particles[j].mass * s.y.segment<3>(particleOffset(nb, j) + 3);
  return p;
}

Vec3 angularMomentum(const Model& m, const State& s) {
  Vec3 L = Vec3::Zero();
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i)
    L += bodyPos(s.y, i).cross(m.bodies[i].mass * bodyVel(s.y, i)) + bodyMom(s.y, i);
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j) {
    const int o = particleOffset(nb, j);
    L += s.y.segment<3>(o).cross(m.particles[j].mass * s.y.segment<3>(o + 3));
  }
  return L;
}

namespace {
bool fail(State& s, Health h, const std::string& why) {
  s.health = h;
  s.health_reason = why;
  return false;
}

// Whether every entry is finite: x - x is 0 for a finite x and NaN for a
// NaN or an infinity, and a sum of such terms is 0 exactly when all are.
// Two lanes at a time (SSE2, the baseline build); Eigen's allFinite took
// ~8 instructions an entry, 5% of a ring-car step.
bool allFinite(const Eigen::VectorXd& y) {
  using v2d = double __attribute__((vector_size(16)));
  const double* p = y.data();
  const Eigen::Index n = y.size();
  v2d acc = {0.0, 0.0};
  Eigen::Index i = 0;
  for (; i + 2 <= n; i += 2) {
    v2d v;
    std::memcpy(&v, p + i, sizeof v);
    acc += v - v;
  }
  double rest = acc[0] + acc[1];
  for (; i < n; ++i) rest += p[i] - p[i];
  return rest == 0.0;
}

}  // namespace

bool checkHealth(const Model& m, State& s, Workspace& ws, bool check_energy) {
  if (s.health != Health::Ok) return false;
  if (!allFinite(s.y)) return fail(s, Health::NonFinite, "state became NaN or infinite");
  const Limits& lim = m.opt.limits;
  if (ws.max_depth > lim.max_penetration) {
    std::ostringstream o;
    o << "penetration " << ws.max_depth << " m exceeds limit " << lim.max_penetration
      << " m (ground too soft or step too large)";
    return fail(s, Health::Penetration, o.str());
  }
  const int nb = static_cast<int>(m.bodies.size());
  // the largest squared speed, then one root: sqrt is monotonic and
  // correctly rounded, so this is the largest norm bit for bit
  double v2max = 0.0;
  for (int i = 0; i < nb; ++i) v2max = std::max(v2max, bodyVel(s.y, i).squaredNorm());
  for (int j = 0; j < static_cast<int>(m.particles.size()); ++j)
    v2max = std::max(v2max, s.y.segment<3>(particleOffset(nb, j) + 3).squaredNorm());
  const double vmax = std::sqrt(v2max);
  if (vmax > lim.max_speed) {
    std::ostringstream o;
    o << "speed " << vmax << " m/s exceeds limit " << lim.max_speed << " m/s";
    return fail(s, Health::Speed, o.str());
  }
  if (check_energy) {
    const double e = computeEnergy(m, s, *ws.diagnostics).total();
    double weight = 0.0;
    for (const Body& b : m.bodies) weight += b.mass * m.opt.gravity.norm();
    for (const Particle& p : m.particles) weight += p.mass * m.opt.gravity.norm();
    const double allowed = lim.max_energy_growth *
                           (std::abs(s.initial_energy) + std::abs(s.drive_work) + weight * 1.0);
    const double excess = e - (s.initial_energy + s.drive_work);
    if (!std::isfinite(e) || excess > allowed) {
      std::ostringstream o;
      o << "energy grew by " << excess << " J beyond the initial energy plus drive work (allowed "
        << allowed << " J)";
      return fail(s, Health::Energy, o.str());
    }
  }
  return true;
}

}  // namespace groundsim
