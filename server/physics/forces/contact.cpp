// Ground contact (report eq. 10): for a point below H = 0, a penalty force
// S * depth along the unit normal, depth = -H / |grad H|, plus normal
// damping; then Coulomb friction. Rim points are tested one by one; a
// continuous wheel touches at the deepest point of its circle.
#include <cmath>

#include "physics/base/pointwise.hpp"
#include "physics/forces/forces.hpp"

namespace groundsim {
namespace {

// Adds a contact at world point p if it is below the ground.
void addContact(Workspace& ws, const Vec3& p, const Vec3& u, int point, int body,
                int particle, int wheel, const Vec3& com) {
  Vec3 g;
  const double H = ws.ground.eval(p, &g);
  if (!(H < 0.0)) return;
  const double gn = g.norm();
  if (!(gn > 0.0)) return;  // degenerate surface point: no normal, no force
  Contact& c = ws.contacts[ws.ncontacts++];
  c.point = point;
  c.body = body;
  c.particle = particle;
  c.wheel = wheel;
  c.p = p;
  c.n = g / gn;
  c.r = p - com;
  c.depth = -H / gn;
  c.normal = 0.0;
  c.friction.setZero();
  c.u = u;
  c.slip = u - u.dot(c.n) * c.n;
}

// Deepest point of a wheel's circle: start from the direction of steepest
// descent of H projected into the wheel plane, then repeat at the new point
// (exact in one pass for a plane; two more passes settle curved grounds).
Vec3 lowestCirclePoint(Workspace& ws, const Vec3& centre, const Vec3& axis, double radius) {
  Vec3 g;
  Vec3 p = centre;
  for (int iter = 0; iter < 3; ++iter) {
    ws.ground.eval(p, &g);
    Vec3 d = -(g - g.dot(axis) * axis);
    const double dn = d.norm();
    d = dn < 1e-12 ? axis.unitOrthogonal() : Vec3(d / dn);  // lying flat: any rim point
    const Vec3 next = centre + radius * d;
    const bool settled = iter > 0 && (next - p).squaredNorm() < 1e-24 * radius * radius;
    p = next;
    if (settled) break;  // a plane settles at once
  }
  return p;
}

}  // namespace

void detectGroundContacts(const Model& m, Workspace& ws) {
  ws.ncontacts = 0;
  ws.max_depth = 0.0;
  const double L = m.ground->gradientBound();
  Vec3 g;
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const Body& b = m.bodies[i];
    // broad phase: H(centre) > L * radius proves the whole ball is above the
    // ground, so none of the body's points (nor its wheel circle) can touch
    ws.body_far[i] = !b.has_contact_points ||
                     (m.opt.broad_phase && std::isfinite(L) &&
                      ws.ground.eval(ws.com[i], &g) > L * b.bound_radius * 1.000001);
    if (ws.body_far[i]) continue;
    const int begin = m.body_point_begin[i], end = m.body_point_end[i];
    ws.ground.heights(ws.px.data(), ws.py.data(), ws.pz.data(), begin, end, ws.H.data());
    for (int k = begin; k < end; ++k)
      if (ws.H[k] < 0.0 && m.points[k].contact)
        addContact(ws, ws.pointPos(k), ws.pointVel(k), k, static_cast<int>(i), -1, m.points[k].wheel,
                   ws.com[i]);
  }
  for (size_t j = 0; j < m.particles.size(); ++j) {
    const int k = m.particle_points[j];
    if (m.particles[j].contact)
      addContact(ws, ws.pointPos(k), ws.pointVel(k), k, -1, static_cast<int>(j), m.points[k].wheel,
                 ws.pointPos(k));
  }
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const Wheel& wh = m.wheels[w];
    if (wh.contact != WheelContact::Circle || ws.body_far[wh.body]) continue;
    const Vec3 axis = ws.R[wh.body] * wh.axis;
    const Vec3 p = lowestCirclePoint(ws, ws.com[wh.body], axis, wh.radius);
    const Vec3 u = ws.vel[wh.body] + ws.omega[wh.body].cross(p - ws.com[wh.body]);
    addContact(ws, p, u, -1, wh.body, -1, static_cast<int>(w), ws.com[wh.body]);
  }
  for (int c = 0; c < ws.ncontacts; ++c) ws.max_depth = std::max(ws.max_depth, ws.contacts[c].depth);
  for (int c = 0; c < ws.ncontacts; ++c) ws.contacts[c].mu = m.ground->friction(ws.contacts[c].p, m.opt.contact.friction);
}

void applyContactNormals(const Model& m, Workspace& ws) {
  const ContactParams& cp = m.opt.contact;
  ws.ground_energy = 0.0;
  for (auto& v : ws.wheel_normal) v = 0.0;
  for (int i = 0; i < ws.ncontacts; ++i) {
    Contact& c = ws.contacts[i];
    const double rate = -c.u.dot(c.n);  // d(depth)/dt
    const double S = groundStiffness(m, c.body), D = groundDamping(m, c.body);
    c.normal = pointwise::penaltyNormal(S, c.depth, D, rate, cp.damping_model == NormalDamping::HuntCrossley);
    ws.ground_energy += 0.5 * S * c.depth * c.depth;
    if (c.wheel >= 0) ws.wheel_normal[c.wheel] += c.normal;
  }
}

void applyExplicitFriction(const Model& m, Workspace& ws) {
  const ContactParams& cp = m.opt.contact;
  for (auto& v : ws.wheel_friction) v = 0.0;
  for (auto& v : ws.wheel_slip) v = 0.0;
  for (int i = 0; i < ws.ncontacts; ++i) {
    Contact& c = ws.contacts[i];
    const double s = c.slip.norm();
    if (c.wheel >= 0) ws.wheel_slip[c.wheel] = std::max(ws.wheel_slip[c.wheel], s);
    if (cp.friction_model == FrictionModel::StickSlip || s == 0.0) continue;
    const double scale = cp.friction_model == FrictionModel::Sign
                             ? 1.0
                             : std::tanh(s / cp.slip_velocity);
    c.friction = -c.mu * c.normal * scale / s * c.slip;
    if (c.wheel >= 0) ws.wheel_friction[c.wheel] += c.friction.norm();
  }
}

}  // namespace groundsim
