// Contact between bodies: broad phase (a box per collision group, sorted and
// swept along x) and narrow phase (every probe of one group of a pair
// against every shape of the other, both ways), with the report's eq. (10)
// at each probe inside a shape. See collision.hpp and docs/contact.md.
#include "physics/forces/body_contact.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace groundsim {
namespace {

constexpr double kPi = 3.14159265358979323846;
// what a group's pad for the step's motion adds, and the census's reach
// for a probe beside a shape: 1 cm
constexpr double kPadSlack = 0.01;  // m

double reducedMass(const CollisionGroup& a, const CollisionGroup& b);

bool live(const CollisionGroup& g) { return g.collider_begin < g.collider_end || g.probe_begin < g.probe_end; }

// Each group's world box for the sweep: for a movable group the box around
// its bounding sphere, grown by `pad(group)` (what it can move in the
// step). Its oriented box is built only when a pair reaches the closer
// check (orientedBox): most groups of a spread scene never need one, and
// the fast paths' steps cost a few microseconds.
template <class RefCom, class Pad>
void groupBoxes(const Model& m, Workspace& ws, RefCom com, Pad pad) {
  for (size_t i = 0; i < m.groups.size(); ++i) {
    const CollisionGroup& g = m.groups[i];
    if (g.ref_body < 0) {
      ws.group_lo[i] = g.lo;
      ws.group_hi[i] = g.hi;
      ws.group_com[i] = 0.5 * (g.lo + g.hi);
      ws.group_pad[i] = 0.0;
      continue;
    }
    const Vec3 c = com(g.ref_body);
    const double p = pad(g);
    const Vec3 s = Vec3::Constant(g.bound + p);
    ws.group_lo[i] = c - s;
    ws.group_hi[i] = c + s;
    ws.group_com[i] = c;
    ws.group_pad[i] = p;
    ws.group_box[i].h.x() = -1.0;  // not built for this evaluation
  }
}

// A movable group's oriented box, built on first use in an evaluation.
template <class RefRot>
const OrientedBox& orientedBox(const Model& m, int i, Workspace& ws, RefRot rot) {
  OrientedBox& box = ws.group_box[i];
  if (box.h.x() >= 0.0) return box;
  const CollisionGroup& g = m.groups[i];
  box.R = rot(g.ref_body);
  box.c = ws.group_com[i] + box.R * g.box_c;
  box.h = g.box_h + Vec3::Constant(ws.group_pad[i]);
  return box;
}

// After the world boxes overlap: two movable groups' bounding spheres and
// oriented boxes must overlap; a movable group must reach a static group's
// shape (its distance function within the sphere, and the shape's box
// overlapping the oriented box: a long diagonal wall has a large world
// box), or hold one of its points.
template <class RefRot>
bool closeEnough(const Model& m, int a, int b, Workspace& ws, RefRot rot) {
  const CollisionGroup &ga = m.groups[a], &gb = m.groups[b];
  const bool sa = ga.ref_body < 0, sb = gb.ref_body < 0;
  if (!sa && !sb) {
    const double r = ga.bound + ws.group_pad[a] + gb.bound + ws.group_pad[b];
    if ((ws.group_com[a] - ws.group_com[b]).squaredNorm() > r * r) return false;
    return overlap(orientedBox(m, a, ws, rot), orientedBox(m, b, ws, rot));
  }
  const CollisionGroup& moving = sa ? gb : ga;
  const CollisionGroup& fixed = sa ? ga : gb;
  const int mi = sa ? b : a;
  const Vec3 c = ws.group_com[mi];
  const double reach = moving.bound + ws.group_pad[mi];
  for (int i = fixed.collider_begin; i < fixed.collider_end; ++i) {
    const Collider& col = m.colliders[i];
    if (col.shape.distance(col.rot.transpose() * (c - col.pos)) > reach) continue;
    if (overlap(orientedBox(m, mi, ws, rot), OrientedBox{col.pos, col.rot, col.shape.extents()})) return true;
  }
  // its probes (a static group's points) may still poke into the group
  for (int i = fixed.probe_begin; i < fixed.probe_end; ++i) {
    if ((m.probes[i].local - c).squaredNorm() > reach * reach) continue;
    if (contains(orientedBox(m, mi, ws, rot), m.probes[i].local, 0.0)) return true;
  }
  return false;
}

// Sort and sweep: the order is kept between evaluations, so the insertion
// sort costs about one comparison per group once bodies move smoothly.
template <class RefRot>
void sweep(const Model& m, Workspace& ws, RefRot rot) {
  std::vector<int>& o = ws.sweep;
  for (size_t i = 1; i < o.size(); ++i) {
    const int g = o[i];
    const double x = ws.group_lo[g].x();
    size_t j = i;
    while (j > 0 && ws.group_lo[o[j - 1]].x() > x) {
      o[j] = o[j - 1];
      --j;
    }
    o[j] = g;
  }
  ws.pairs.clear();
  for (size_t i = 0; i < o.size(); ++i) {
    const int a = o[i];
    if (!live(m.groups[a])) continue;
    for (size_t j = i + 1; j < o.size(); ++j) {
      const int b = o[j];
      if (ws.group_lo[b].x() > ws.group_hi[a].x()) break;
      if (!live(m.groups[b]) || (m.groups[a].ref_body < 0 && m.groups[b].ref_body < 0)) continue;
      if (ws.group_lo[b].y() > ws.group_hi[a].y() || ws.group_lo[a].y() > ws.group_hi[b].y() ||
          ws.group_lo[b].z() > ws.group_hi[a].z() || ws.group_lo[a].z() > ws.group_hi[b].z())
        continue;
      if (!closeEnough(m, a, b, ws, rot)) continue;
      ws.pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
}

struct PairLaw {
  double k = 0.0, c = 0.0, mu = 0.0, vs = 0.05;
};

PairLaw pairLaw(const Model& m, const CollisionGroup& a, const CollisionGroup& b) {
  const CollisionParams& cp = m.opt.collision;
  const double mr = reducedMass(a, b);
  PairLaw law;
  const double w = 2.0 * kPi * cp.frequency;
  law.k = cp.stiffness > 0.0 ? cp.stiffness : 0.25 * mr * w * w;
  law.c = cp.damping >= 0.0 ? cp.damping : cp.damping_ratio * std::sqrt(law.k * mr);
  law.mu = std::sqrt(std::max(a.friction, 0.0) * std::max(b.friction, 0.0));
  law.vs = cp.slip_velocity;
  return law;
}

// Whether every probe and shape of the group moves with its reference body
// (a road car, an object with mass) or it is static: then its contact
// forces act on that one body, and a pair's stiffest mode follows from a
// census of the probes that press or can press in the step (pairSubsteps).
bool censusApplies(const CollisionGroup& g) { return g.rigid || g.ref_body < 0; }

// The world pose of a collider, and the velocity of its body at a point.
struct Frame {
  Mat3 R = Mat3::Identity();
  Vec3 o = Vec3::Zero();
};
Frame colliderFrame(const Collider& c, const Workspace& ws) {
  if (c.body < 0) return {c.rot, c.pos};
  return {ws.R[c.body] * c.rot, ws.com[c.body] + ws.R[c.body] * c.pos};
}
Vec3 bodyPointVelocity(int body, const Vec3& p, const Workspace& ws) {
  return body < 0 ? Vec3::Zero() : Vec3(ws.vel[body] + ws.omega[body].cross(p - ws.com[body]));
}

// The deepest point of a wheel's circle in a shape: start towards the
// shape's centre, then follow the shape's inward normal projected into the
// wheel plane (as contact.cpp does for the ground).
Vec3 deepestCirclePoint(const Shape& s, const Frame& f, const Vec3& centre, const Vec3& axis, double radius) {
  Vec3 d = f.o - centre;
  d -= d.dot(axis) * axis;
  const double dn = d.norm();
  d = dn > 1e-12 ? Vec3(d / dn) : axis.unitOrthogonal();
  Vec3 p = centre + radius * d;
  for (int iter = 0; iter < 3; ++iter) {
    Vec3 g = f.R * s.normal(f.R.transpose() * (p - f.o));
    g = -(g - g.dot(axis) * axis);
    const double gn = g.norm();
    if (!(gn > 1e-12)) break;
    p = centre + radius * (g / gn);
  }
  return p;
}

// Probe pi of group P (whose bodies it moves with: pb) against collider
// col of group C at frame f, whose bounding sphere has radius reach: the
// report's eq. (10) if it is inside, added
// to the pair's telemetry and, with apply, to both bodies.
void probeInto(const Model& m, int P, int pi, const Collider& col, const Frame& f, double reach, const PairLaw& law,
               bool apply, Workspace& ws, PairContact& pc) {
  const Probe& pr = m.probes[pi];
  Vec3 p;
  int moving = -1;  // the body whose velocity at p is the probe's, once it is inside
  if (pr.wheel >= 0) {
    const Wheel& wh = m.wheels[pr.wheel];
    const Vec3 centre = ws.com[wh.body];
    if ((centre - f.o).norm() > reach + wh.radius) return;
    p = deepestCirclePoint(col.shape, f, centre, ws.R[wh.body] * wh.axis, wh.radius);
    moving = wh.body;
  } else if (pr.point >= 0) {
    p = ws.pointPos(pr.point);
    if ((p - f.o).squaredNorm() > reach * reach) return;
  } else if (pr.body >= 0) {
    p = ws.com[pr.body] + ws.R[pr.body] * pr.local;
    if ((p - f.o).squaredNorm() > reach * reach) return;
    moving = pr.body;
  } else {
    p = pr.local;
    if ((p - f.o).squaredNorm() > reach * reach) return;
  }
  const Vec3 q = f.R.transpose() * (p - f.o);
  const double dist = col.shape.distance(q);
  if (!(dist < 0.0)) return;
  // the probe's velocity, only for a probe inside
  const Vec3 u = moving >= 0     ? bodyPointVelocity(moving, p, ws)
                 : pr.point >= 0 ? ws.pointVel(pr.point)
                                 : Vec3(Vec3::Zero());
  const double depth = -dist;
  const Vec3 n = f.R * col.shape.normal(q);  // out of the shape: pushes the probe out
  const Vec3 rel = u - bodyPointVelocity(col.body, p, ws);
  const double N = std::max(law.k * depth - law.c * rel.dot(n), 0.0);
  const Vec3 slip = rel - rel.dot(n) * n;
  const double s = slip.norm();
  Vec3 F = N * n;
  if (s > 0.0 && law.mu > 0.0) F -= (law.mu * N * std::tanh(s / law.vs) / s) * slip;
  ws.body_contact_energy += 0.5 * law.k * depth * depth;
  ws.body_contact_depth = std::max(ws.body_contact_depth, depth);
  ++pc.points;
  pc.normal += N;
  pc.where += N * p;
  pc.depth = std::max(pc.depth, depth);
  pc.force += P == pc.a ? F : Vec3(-F);
  if (!apply) return;
  const int pb = pr.wheel >= 0 ? m.wheels[pr.wheel].body : pr.point >= 0 ? m.points[pr.point].body : pr.body;
  if (pr.particle >= 0) {
    ws.particle_force[pr.particle] += F;
  } else if (pb >= 0) {
    ws.body_force[pb] += F;
    ws.body_torque[pb] += (p - ws.com[pb]).cross(F);
  }
  if (col.body >= 0) {
    ws.body_force[col.body] -= F;
    ws.body_torque[col.body] -= (p - ws.com[col.body]).cross(F);
  }
}

// Probes of group P against the shapes of group C.
void probesInto(const Model& m, int P, int C, const PairLaw& law, bool apply, Workspace& ws, PairContact& pc) {
  const CollisionGroup& gp = m.groups[P];
  const CollisionGroup& gc = m.groups[C];
  // A rigid group's probes lie in its box (box_c, box_h, in its reference
  // body's frame): a shape whose own box, seen as a box of that frame,
  // misses it reaches none of them, and a probe fixed to that body is
  // tested against the shape's bounding sphere and that box in the body's
  // frame, with no rotation per probe. These only skip work: a probe they
  // pass meets the world-frame test of probeInto (so the same probes
  // reach the shape, bit for bit), and the 1 mm of slack covers the
  // round-off between the two frames.
  constexpr double kSlack = 1e-3;  // m
  const int rb = gp.rigid ? gp.ref_body : -1;
  for (int ci = gc.collider_begin; ci < gc.collider_end; ++ci) {
    const Collider& col = m.colliders[ci];
    const Frame f = colliderFrame(col, ws);
    const double reach = col.shape.bound();
    Vec3 c_local = Vec3::Zero();  // the shape's origin in rb's frame
    Vec3 c_half = Vec3::Zero();   // half extents of the shape's box, as a box of rb's frame
    const double cull = (reach + kSlack) * (reach + kSlack);
    if (rb >= 0) {
      const Mat3 Rt = ws.R[rb].transpose();
      c_local = Rt * (f.o - ws.com[rb]);
      c_half = (Rt * f.R).cwiseAbs() * col.shape.extents() + Vec3::Constant(kSlack);
      if (((c_local - gp.box_c).cwiseAbs() - gp.box_h - c_half).maxCoeff() > 0.0) continue;
    }
    for (int pi = gp.probe_begin; pi < gp.probe_end; ++pi) {
      const Probe& pr = m.probes[pi];
      if (rb >= 0 && pr.body == rb && pr.wheel < 0 && pr.point < 0 &&
          ((pr.local - c_local).squaredNorm() > cull || ((pr.local - c_local).cwiseAbs() - c_half).maxCoeff() > 0.0))
        continue;
      probeInto(m, P, pi, col, f, reach, law, apply, ws, pc);
    }
  }
}

// The probes of group P the step's census listed, against their shapes
// of group C: the same tests and forces as probesInto, in its order, over
// the probes that can touch in this step only.
void listedProbesInto(const Model& m, int P, const Workspace::CensusProbe* begin, const Workspace::CensusProbe* end,
                      const PairLaw& law, bool apply, Workspace& ws, PairContact& pc) {
  int frame_of = -1;
  Frame f;
  double reach = 0.0;
  for (const Workspace::CensusProbe* e = begin; e != end; ++e) {
    const Collider& col = m.colliders[e->collider];
    if (e->collider != frame_of) {
      f = colliderFrame(col, ws);
      reach = col.shape.bound();
      frame_of = e->collider;
    }
    probeInto(m, P, e->probe, col, f, reach, law, apply, ws, pc);
  }
}

void narrowPhase(const Model& m, bool apply, Workspace& ws) {
  ws.body_contact_energy = 0.0;
  ws.body_contact_depth = 0.0;
  ws.pair_contacts.clear();
  const bool listed = ws.step_pairs && ws.step_census;
  for (size_t k = 0; k < ws.pairs.size(); ++k) {
    const auto [a, b] = ws.pairs[k];
    PairContact pc;
    pc.a = a;
    pc.b = b;
    const PairLaw law = pairLaw(m, m.groups[a], m.groups[b]);
    if (listed && ws.census_range[k][0] >= 0) {
      const std::array<int, 3>& r = ws.census_range[k];
      const Workspace::CensusProbe* c = ws.census.data();
      listedProbesInto(m, a, c + r[0], c + r[1], law, apply, ws, pc);
      listedProbesInto(m, b, c + r[1], c + r[2], law, apply, ws, pc);
    } else {
      probesInto(m, a, b, law, apply, ws, pc);
      probesInto(m, b, a, law, apply, ws, pc);
    }
    if (pc.points == 0) continue;
    pc.where = pc.normal > 0.0 ? Vec3(pc.where / pc.normal) : Vec3::Zero();
    ws.pair_contacts.push_back(pc);
  }
}

double reducedMass(const CollisionGroup& a, const CollisionGroup& b) {
  const bool fa = a.ref_body < 0 || !(a.mass > 0.0), fb = b.ref_body < 0 || !(b.mass > 0.0);
  return fa ? b.mass : fb ? a.mass : a.mass * b.mass / (a.mass + b.mass);
}

}  // namespace

int substepsFor(double omega, double zeta, double dt) {
  const double limit = 2.0 * (std::sqrt(1.0 + zeta * zeta) - zeta);
  const double n = std::ceil(omega * dt / (kStepMargin * limit));
  return std::isfinite(n) ? static_cast<int>(std::clamp(n, 1.0, static_cast<double>(kMaxContactSubsteps)))
                          : kMaxContactSubsteps;
}

namespace {

// One side of a pair for the census: a rigid group's reference body at the
// step's start (com, rotation, inverse mass and inertia), or a static group.
struct CensusSide {
  bool movable = false;
  Vec3 com = Vec3::Zero();
  Mat3 R = Mat3::Identity();
  double inv_mass = 0.0;
  Mat3 inv_inertia = Mat3::Zero();  // body frame
  Mat3 L = Mat3::Zero();            // L L^T = inv_inertia
  Vec3 vel = Vec3::Zero(), omega = Vec3::Zero();
  Vec3 velocityAt(const Vec3& p) const { return movable ? Vec3(vel + omega.cross(p - com)) : Vec3(Vec3::Zero()); }
};

CensusSide censusSide(const Model& m, const CollisionGroup& g, const Eigen::VectorXd& y) {
  CensusSide s;
  if (g.ref_body < 0 || !(g.mass > 0.0)) return s;
  s.movable = true;
  s.com = bodyPos(y, g.ref_body);
  s.R = Quat(bodyRot(y, g.ref_body)).normalized().toRotationMatrix();
  s.inv_mass = 1.0 / m.bodies[g.ref_body].mass;
  s.inv_inertia = m.bodies[g.ref_body].inv_inertia;
  s.L = Eigen::LLT<Mat3>(s.inv_inertia).matrixL();
  s.vel = bodyVel(y, g.ref_body);
  s.omega = s.R * (s.inv_inertia * (s.R.transpose() * Vec3(bodyMom(y, g.ref_body))));
  return s;
}

// A unit force along n at world point p, in this side's mass-weighted
// coordinates (translation scaled by 1/sqrt(m), rotation by L^T in the body
// frame): its squared norm is the inverse mass the force meets,
// 1/m + (r x n)^T I^-1 (r x n).
using Gen6 = Eigen::Matrix<double, 6, 1>;
Gen6 massWeighted(const CensusSide& s, const Vec3& p, const Vec3& n) {
  Gen6 g = Gen6::Zero();
  if (!s.movable) return g;
  g.head<3>() = std::sqrt(s.inv_mass) * n;
  g.tail<3>() = s.L.transpose() * (s.R.transpose() * Vec3((p - s.com).cross(n)));
  return g;
}


// A probe of a rigid or static group, in the world at the step's start.
Vec3 censusProbe(const Model& m, const Probe& pr, const CensusSide& s) {
  if (!s.movable) return pr.local;
  return s.com + s.R * (pr.point >= 0 ? m.points[pr.point].local : pr.local);
}

// Over the probes of group P that are inside a shape of group C or within
// reach of one (twice what their relative velocity covers in dt, and 1 cm:
// where the step's motion can bring them): adds g g^T to A, g the probe's
// unit normal force in both sides' mass-weighted coordinates (P's force
// on its side, the reaction on C's). `reach` bounds every probe's (the
// pair's pads) and culls the rest.
using Gen12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
// Each probe counted is listed in `listed` as (probe, collider), in the
// narrow phase's order.
int censusInto(const Model& m, const CollisionGroup& gp, const CensusSide& sp, const CollisionGroup& gc,
               const CensusSide& sc, double reach, double dt, bool p_first, Mat12& A,
               std::vector<Workspace::CensusProbe>& listed) {
  int count = 0;
  for (int ci = gc.collider_begin; ci < gc.collider_end; ++ci) {
    const Collider& col = m.colliders[ci];
    const Mat3 R = sc.movable ? Mat3(sc.R * col.rot) : col.rot;
    const Vec3 o = sc.movable ? Vec3(sc.com + sc.R * col.pos) : col.pos;
    const double cull = col.shape.bound() + reach;
    // the shape's frame from P's: q = Q local + t (a static P: Q = R^T)
    const Mat3 Q = sp.movable ? Mat3(R.transpose() * sp.R) : Mat3(R.transpose());
    const Vec3 t = R.transpose() * ((sp.movable ? sp.com : Vec3(Vec3::Zero())) - o);
    // culled in P's frame first, as probesInto does: the shape's box (grown
    // by the reach) as a box of that frame, no rotation per probe
    const Vec3 o_local = sp.movable ? Vec3(sp.R.transpose() * (o - sp.com)) : o;
    const Vec3 o_half = Q.transpose().cwiseAbs() * col.shape.extents() + Vec3::Constant(reach);
    if (sp.movable && ((o_local - gp.box_c).cwiseAbs() - gp.box_h - o_half).maxCoeff() > 0.0) continue;
    // then run by run: a run whose box misses the shape's holds no probe that reaches it
    for (int k = gp.chunk_begin; k < gp.chunk_end; ++k) {
      const ProbeChunk& ch = m.probe_chunks[k];
      if (((ch.c - o_local).cwiseAbs() - ch.h - o_half).maxCoeff() > 0.0) continue;
      for (int pi = ch.begin; pi < ch.end; ++pi) {
        const Probe& pr = m.probes[pi];
        const Vec3& local = pr.point >= 0 ? m.points[pr.point].local : pr.local;
        if ((local - o_local).squaredNorm() > cull * cull || ((local - o_local).cwiseAbs() - o_half).maxCoeff() > 0.0)
          continue;
        const Vec3 q = Q * local + t;
        const double d = col.shape.distance(q);
        if (!(d < reach)) continue;
        const Vec3 p = censusProbe(m, pr, sp);
        if (d > 0.0 && !(d < 2.0 * (sp.velocityAt(p) - sc.velocityAt(p)).norm() * dt + kPadSlack)) continue;
        const Vec3 n = R * col.shape.normal(q);
        Gen12 g;
        g.head<6>() = massWeighted(p_first ? sp : sc, p, p_first ? n : Vec3(-n));
        g.tail<6>() = massWeighted(p_first ? sc : sp, p, p_first ? Vec3(-n) : n);
        for (int j = 0; j < 12; ++j)  // g g^T, lower half (largestEigenvalueBound reads it as symmetric)
          for (int i = j; i < 12; ++i) A(i, j) += g[i] * g[j];
        listed.push_back({pi, ci});
        ++count;
      }
    }
  }
  return count;
}

// An upper bound of the largest eigenvalue of a symmetric positive
// semidefinite A that is within a factor rank^(1/8) of it: the Frobenius
// norm of A^4 to the power 1/4 (every eigenvalue of A^4 is the fourth power
// of one of A's, and the Frobenius norm is the root of their squares' sum).
double largestEigenvalueBound(const Mat12& lower) {
  const Mat12 A = lower.selfadjointView<Eigen::Lower>();
  const Mat12 A2 = A * A;
  const Mat12 A4 = A2 * A2;
  return std::sqrt(std::sqrt(A4.norm()));
}

// The face-probe bound: every face probe of both groups pressing at once
// on the pair's reduced mass m_r (> 0).
int faceProbeSubsteps(const PairLaw& law, const CollisionGroup& ga, const CollisionGroup& gb, double mr, double dt) {
  const double probes = ga.face_probes + gb.face_probes;
  const double k = law.k * probes, c = law.c * probes;
  return substepsFor(std::sqrt(k / mr), c / (2.0 * std::sqrt(k * mr)), dt);
}

// Substeps for one pair. The probes that press (or can, in the step) are
// springs k and dampers c between two rigid bodies: their modes are the
// eigenvalues of k A, A = sum of g g^T in mass-weighted coordinates (g: a
// probe's equal and opposite unit forces, with their lever arms), so the
// stiffest is omega^2 = k lambda_max(A), taken from a bound within 12^(1/8)
// of it; with one c/k for every probe each mode's damping ratio is
// c omega / 2k (C is proportional to K). Exact where the old bound, every
// face probe of both groups pressing at once on the reduced mass, ignored
// the lever arms and counted probes that cannot touch. A pair whose parts
// do not all move with its reference bodies (the report's cars of mass
// points) still takes that bound.
// The census's probes are kept as the pair's census_range in ws (a's,
// then b's): the step's evaluations test only those.
int pairSubsteps(const Model& m, const Eigen::VectorXd& y, Workspace& ws, size_t pair, double dt) {
  const auto [a, b] = ws.pairs[pair];
  const CollisionGroup &ga = m.groups[a], &gb = m.groups[b];
  const PairLaw law = pairLaw(m, ga, gb);
  const double mr = reducedMass(ga, gb);
  if (!(mr > 0.0)) return 1;
  if (!censusApplies(ga) || !censusApplies(gb)) return faceProbeSubsteps(law, ga, gb, mr, dt);
  const CensusSide sa = censusSide(m, ga, y), sb = censusSide(m, gb, y);
  const double reach = ws.group_pad[a] + ws.group_pad[b];
  Mat12 A = Mat12::Zero();
  std::array<int, 3>& range = ws.census_range[pair];
  range[0] = static_cast<int>(ws.census.size());
  int count = censusInto(m, ga, sa, gb, sb, reach, dt, true, A, ws.census);
  range[1] = static_cast<int>(ws.census.size());
  count += censusInto(m, gb, sb, ga, sa, reach, dt, false, A, ws.census);
  range[2] = static_cast<int>(ws.census.size());
  if (count == 0 || !(law.k > 0.0)) return 1;
  const double top = largestEigenvalueBound(A);
  const double omega = std::sqrt(law.k * std::max(top, 0.0));
  return substepsFor(omega, law.c * omega / (2.0 * law.k), dt);
}

}  // namespace

int contactSubsteps(const Model& m, const Eigen::VectorXd& y, Workspace& ws, double dt) {
  ws.census.clear();
  ws.census_range.assign(ws.pairs.size(), {-1, -1, -1});
  int n = 1;
  for (size_t k = 0; k < ws.pairs.size(); ++k) n = std::max(n, pairSubsteps(m, y, ws, k, dt));
  ws.step_census = ws.step_pairs;
  return n;
}

int contactSubstepsBound(const Model& m, double dt) {
  int n = std::max(1, m.object_substeps);
  if (!m.collisions) return n;
  for (size_t a = 0; a < m.groups.size(); ++a)
    for (size_t b = a + 1; b < m.groups.size(); ++b) {
      const CollisionGroup &ga = m.groups[a], &gb = m.groups[b];
      if (ga.ref_body < 0 && gb.ref_body < 0) continue;  // two static groups never meet
      const PairLaw law = pairLaw(m, ga, gb);
      const double mr = reducedMass(ga, gb);
      if (!(mr > 0.0)) continue;
      n = std::max(n, faceProbeSubsteps(law, ga, gb, mr, dt));
    }
  return n;
}

bool groupsMayTouch(const Model& m, const Eigen::VectorXd& y, double dt, Workspace& ws) {
  if (!m.collisions) return false;
  // pad each movable group by twice what its reference body's motion
  // covers in the step (and 1 cm): its speed, and its turn rate (at most
  // |L| times the largest inverse inertia, bounded by the Frobenius norm)
  // times the bound. A pair that can meet during the step is a candidate
  // from its start.
  groupBoxes(
      m, ws, [&](int body) { return Vec3(bodyPos(y, body)); },
      [&](const CollisionGroup& g) {
        const int b = g.ref_body;
        const double spin = m.bodies[b].inv_inertia.norm() * Vec3(bodyMom(y, b)).norm();
        return 2.0 * (Vec3(bodyVel(y, b)).norm() + spin * g.bound) * dt + kPadSlack;
      });
  sweep(m, ws, [&](int body) { return Mat3(Quat(bodyRot(y, body)).normalized().toRotationMatrix()); });
  return !ws.pairs.empty();
}

void clearBodyContacts(Workspace& ws) {
  ws.pair_contacts.clear();
  ws.body_contact_energy = 0.0;
  ws.body_contact_depth = 0.0;
}

void bodyContacts(const Model& m, bool apply, Workspace& ws) {
  clearBodyContacts(ws);
  if (!m.collisions) return;
  if (!ws.step_pairs) {
    groupBoxes(m, ws, [&](int body) { return ws.com[body]; }, [](const CollisionGroup&) { return 0.0; });
    sweep(m, ws, [&](int body) { return ws.R[body]; });
  }
  narrowPhase(m, apply, ws);
}

}  // namespace groundsim
