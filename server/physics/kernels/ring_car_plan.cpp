// The ring car's plan (ring_car_detail.hpp): what the model must hold for
// the ring-car step, and its rims, plain points, springs, wheels, bodies
// and plane laid out for the evaluation (ring_car.cpp).
#include <algorithm>
#include <vector>

#include "physics/kernels/ring_car.hpp"
#include "physics/kernels/ring_car_detail.hpp"

namespace groundsim::ringcar {

namespace {

// What the ring-car step does not do; the plane's n and offset otherwise.
const char* unsupported(const Model& m, Vec3* n, double* offset) {
  if (m.opt.deterministic) return "physics.deterministic keeps the general loop's bits";
  if (const char* why = rigidStepUnsupported(m)) return why;
  if (m.spring_fans.empty()) return "the model has no spring fans (rims)";
  if (m.wheels.empty() || m.wheels.size() > static_cast<size_t>(kMaxWheels)) return "no wheels or too many";
  for (const Wheel& w : m.wheels)
    if (w.contact != WheelContact::RimPoints) return "a wheel is not a rim of points";
  if (!m.ground || !m.ground->asPlane(n, offset)) return "the ground is not a plane";
  for (const Spring& s : m.springs)
    if (m.points[s.a].body < 0 || m.points[s.b].body < 0) return "a spring is not between body points";
  return nullptr;
}

// A new rim for fan f: its points, which rim_of marks as its.
const char* newRim(const Model& m, const Model::SpringFan& f, Plan* P, std::vector<int>& rim_of) {
  for (int k = f.a0; k < f.a0 + f.count; ++k)
    if (rim_of[k] >= 0) return "two rims overlap";
  P->rims.emplace_back();
  Rim* rim = &P->rims.back();
  rim->a0 = f.a0;
  rim->n = f.count;
  rim->body = m.points[f.a0].body;
  rim->wheel = m.points[f.a0].wheel;
  for (int k = f.a0; k < f.a0 + f.count; ++k) {
    const Point& pt = m.points[k];
    if (pt.body != rim->body || pt.wheel != rim->wheel || pt.steer_wheel >= 0)
      return "a rim's points are not of one unsteered wheel body";
    rim_of[k] = static_cast<int>(P->rims.size()) - 1;
    rim->lx.push_back(pt.local.x());
    rim->ly.push_back(pt.local.y());
    rim->lz.push_back(pt.local.z());
    rim->contact.push_back(pt.contact ? 1 : 0);
  }
  return nullptr;
}

// Rims: fans sharing their first point and count. A fan's far point stays
// a model point for now (plainIndices).
const char* gatherRims(const Model& m, Plan* P, std::vector<int>& rim_of) {
  for (const Model::SpringFan& f : m.spring_fans) {
    Rim* rim = nullptr;
    for (Rim& r : P->rims)
      if (r.a0 == f.a0 && r.n == f.count) rim = &r;
    if (rim == nullptr) {
      if (const char* why = newRim(m, f, P, rim_of)) return why;
      rim = &P->rims.back();
    }
    if (rim->nf == 2) return "a rim has more than two fans";
    const int fi = rim->nf++;
    rim->b[fi] = f.b;  // model point for now
    for (int s = f.first; s < f.first + f.count; ++s) {
      rim->k[fi].push_back(m.spring_k[s]);
      rim->c[fi].push_back(m.spring_c[s]);
      rim->rest[fi].push_back(m.spring_rest[s]);
    }
  }
  return nullptr;
}

// Which bodies are wheels of rims (rim_body), and that nothing else of
// theirs or of their rims' points is left out.
const char* checkRims(const Model& m, const Plan& P, const std::vector<int>& rim_of,
                      std::vector<unsigned char>& rim_body) {
  const size_t nb = m.bodies.size();
  rim_body.assign(nb, 0);
  for (const Rim& r : P.rims) rim_body[r.body] = 1;
  for (size_t i = 0; i < nb; ++i)
    for (int k = m.body_point_begin[i]; k < m.body_point_end[i]; ++k)
      if (rim_body[i] && rim_of[k] < 0) return "a wheel body has points off its rims";
  for (int s : m.loose_springs)
    if (rim_of[m.springs[s].a] >= 0 || rim_of[m.springs[s].b] >= 0) return "a rim point has a spring off its fans";
  for (const Rim& r : P.rims)
    for (int f = 0; f < r.nf; ++f)
      if (rim_of[r.b[f]] >= 0) return "a fan ends on a rim point";
  return nullptr;
}

// Plain points: every point of the other bodies, in body order. Returns
// each model point's plain index (-1: on a rim).
std::vector<int> plainPoints(const Model& m, const std::vector<unsigned char>& rim_body, Plan* P) {
  const size_t np = m.points.size(), nb = m.bodies.size();
  std::vector<int> plain_of(np, -1);
  P->plain_begin.assign(nb, 0);
  P->plain_end.assign(nb, 0);
  for (size_t i = 0; i < nb; ++i) {
    P->plain_begin[i] = static_cast<int>(P->plain.size());
    if (!rim_body[i])
      for (int k = m.body_point_begin[i]; k < m.body_point_end[i]; ++k) {
        const Point& pt = m.points[k];
        plain_of[k] = static_cast<int>(P->plain.size());
        P->plain.push_back({static_cast<int>(i), k, pt.wheel, pt.local.x(), pt.local.y(), pt.local.z(),
                            pt.steer_wheel, pt.steer_pivot.x(), pt.steer_pivot.y(),
                            (pt.local - pt.steer_pivot).x(), (pt.local - pt.steer_pivot).y(), pt.contact});
      }
    P->plain_end[i] = static_cast<int>(P->plain.size());
  }
  return plain_of;
}

// The fans' far points as plain indices; the rims by body, then first
// point (the general path's contact order), and each body's range of them.
void orderRims(const std::vector<int>& plain_of, size_t nb, Plan* P) {
  for (Rim& r : P->rims)
    for (int f = 0; f < r.nf; ++f) r.b[f] = plain_of[r.b[f]];
  std::stable_sort(P->rims.begin(), P->rims.end(),
                   [](const Rim& a, const Rim& b) { return a.body != b.body ? a.body < b.body : a.a0 < b.a0; });
  P->rim_begin.assign(nb, 0);
  P->rim_end.assign(nb, 0);
  for (size_t i = 0, r = 0; i < nb; ++i) {
    P->rim_begin[i] = static_cast<int>(r);
    while (r < P->rims.size() && P->rims[r].body == static_cast<int>(i)) ++r;
    P->rim_end[i] = static_cast<int>(r);
  }
}

// Every rim with two fans and padded to a multiple of four (Rim says why).
void padRims(Plan* P) {
  for (Rim& r : P->rims) {
    if (r.nf == 1) {  // one fan: the second is the first with no force (zero stiffness and damping)
      r.b[1] = r.b[0];
      r.k[1].assign(r.n, 0.0);
      r.c[1].assign(r.n, 0.0);
      r.rest[1].assign(r.n, 0.0);
    }
    r.padded = (r.n + 3) / 4 * 4;
    for (auto* v : {&r.lx, &r.ly, &r.lz, &r.k[0], &r.c[0], &r.rest[0], &r.k[1], &r.c[1], &r.rest[1]})
      v->resize(static_cast<size_t>(r.padded), 0.0);
    r.contact.resize(static_cast<size_t>(r.padded), 0);
    P->max_rim = std::max(P->max_rim, r.padded);
  }
}

// The springs between plain points, the wheels, the bodies' constants.
void springsWheelsBodies(const Model& m, const std::vector<int>& plain_of, Plan* P) {
  for (int s : m.loose_springs) {
    const Spring& sp = m.springs[s];
    P->loose.push_back({plain_of[sp.a], plain_of[sp.b], sp.stiffness, sp.damping, sp.rest_length, sp.isotropic});
  }
  for (const Wheel& w : m.wheels) P->wheels.push_back({w.body, w.carrier, w.axis.x(), w.axis.y(), w.axis.z()});
  for (size_t i = 0; i < m.bodies.size(); ++i) P->rigid.bodies.push_back(bodyConstants(m.bodies[i]));
}

// The plane (its normal, tangent basis, offset), gravity and the contact
// settings.
void planeAndContact(const Model& m, const Vec3& n, double offset, Plan* P) {
  P->gn = n.norm();
  const Vec3 cn = n / P->gn, t1 = cn.unitOrthogonal(), t2 = cn.cross(t1);
  for (int k = 0; k < 3; ++k) {
    P->n[k] = n[k];
    P->cn[k] = cn[k];
    P->t1[k] = t1[k];
    P->t2[k] = t2[k];
    P->gravity[k] = m.opt.gravity[k];
  }
  P->offset = offset;
  P->stiffness = m.opt.contact.stiffness;
  P->damping = m.opt.contact.damping;
  P->hunt_crossley = m.opt.contact.damping_model == NormalDamping::HuntCrossley;
  P->scene_mu = m.opt.contact.friction;
  P->friction_iterations = m.opt.contact.friction_iterations;
}

}  // namespace

const char* buildPlan(const Model& m, Plan* P) {
  Vec3 n;
  double offset = 0.0;
  if (const char* why = unsupported(m, &n, &offset)) return why;
  std::vector<int> rim_of(m.points.size(), -1);
  if (const char* why = gatherRims(m, P, rim_of)) return why;
  std::vector<unsigned char> rim_body;
  if (const char* why = checkRims(m, *P, rim_of, rim_body)) return why;
  const std::vector<int> plain_of = plainPoints(m, rim_body, P);
  orderRims(plain_of, m.bodies.size(), P);
  padRims(P);
  springsWheelsBodies(m, plain_of, P);
  planeAndContact(m, n, offset, P);
  return nullptr;
}

}  // namespace groundsim::ringcar

namespace groundsim {

const char* ringCarUnsupported(const Model& m) {
  ringcar::Plan P;
  return ringcar::buildPlan(m, &P);
}

}  // namespace groundsim
