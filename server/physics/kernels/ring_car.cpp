#include "physics/kernels/ring_car.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <stdexcept>

#include "physics/base/pointwise.hpp"
#include "physics/kernels/fast_car_kernel.hpp"  // the rigid-body helpers shared with the circle-wheel car
#include "physics/forces/forces.hpp"

namespace groundsim {

namespace {

using fastcar::BodyL;

constexpr int kMaxWheels = 16;

// A point not on a rim (an axle point, a chassis contact point): its world
// position, velocity and spring force are kept for the step.
struct PlainPoint {
  int body, model_point, wheel;
  double lx, ly, lz;
  int steer_wheel;  // -1: fixed
  double pivx, pivy, dx, dy;
  bool contact;
};
// Points [a0, a0 + n) of one body (a wheel's rim), each joined by one spring
// of every fan to the fan's far point (an axle point, plain).
// Its arrays are padded to a multiple of four with points at the wheel's
// centre on springs of zero stiffness and damping that touch nothing: they
// add exactly zero, and the 4-wide loops need no remainder.
struct Rim {
  int body = -1, a0 = 0, n = 0, nf = 0, wheel = -1;
  int padded = 0;
  int b[2] = {-1, -1};  // plain index of each fan's far point
  std::vector<double> lx, ly, lz;
  std::vector<unsigned char> contact;
  std::vector<double> k[2], c[2], rest[2];
};
struct LooseSpring {
  int a, b;  // plain indices
  double k, c, rest;
  bool isotropic;
};
struct WheelC {
  int body, carrier;
  double ax, ay, az;
};

struct Plan {
  FastCarPlan rigid;  // bodies only (mass, inverse inertia)
  std::vector<PlainPoint> plain;
  std::vector<int> plain_begin, plain_end;  // (nbody) a body's plain points
  std::vector<int> rim_begin, rim_end;      // (nbody) a body's rims, by a0
  std::vector<Rim> rims;
  std::vector<LooseSpring> loose;
  std::vector<WheelC> wheels;
  double n[3], offset, gn;  // plane H = n . p - offset, gn = |n| as the general path computes it
  double cn[3], t1[3], t2[3];  // unit normal, its tangent basis (Eigen's unitOrthogonal)
  double gravity[3];
  double stiffness, damping, scene_mu;
  bool hunt_crossley;
  int friction_iterations;
  int max_rim = 0;
};

// Builds the plan, or says why the model does not fit.
const char* buildPlan(const Model& m, Plan* P) {
  Vec3 n;
  double offset = 0.0;
  if (m.opt.deterministic) return "physics.deterministic keeps the general loop's bits";
  if (m.opt.integrator != IntegratorKind::SemiImplicitEuler) return "integrator is not semi_implicit_euler";
  if (m.opt.contact.friction_model != FrictionModel::StickSlip) return "friction is not stick_slip";
  if (!m.particles.empty()) return "the model has particles";
  for (const SceneObject& o : m.objects)
    if (o.body >= 0) return "the scene has objects with mass";
  if (!m.road_cars.empty() || m.aux_states != 0) return "the model has road cars";
  if (m.spring_fans.empty()) return "the model has no spring fans (rims)";
  if (m.wheels.empty() || m.wheels.size() > static_cast<size_t>(kMaxWheels)) return "no wheels or too many";
  for (const Wheel& w : m.wheels)
    if (w.contact != WheelContact::RimPoints) return "a wheel is not a rim of points";
  if (!m.ground || !m.ground->asPlane(&n, &offset)) return "the ground is not a plane";
  for (const Spring& s : m.springs)
    if (m.points[s.a].body < 0 || m.points[s.b].body < 0) return "a spring is not between body points";
  const size_t np = m.points.size(), nb = m.bodies.size();
  // rims: fans sharing their first point and count
  std::vector<int> rim_of(np, -1);
  for (const Model::SpringFan& f : m.spring_fans) {
    Rim* rim = nullptr;
    for (Rim& r : P->rims)
      if (r.a0 == f.a0 && r.n == f.count) rim = &r;
    if (rim == nullptr) {
      for (int k = f.a0; k < f.a0 + f.count; ++k)
        if (rim_of[k] >= 0) return "two rims overlap";
      P->rims.emplace_back();
      rim = &P->rims.back();
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
  std::vector<unsigned char> rim_body(nb, 0);
  for (const Rim& r : P->rims) rim_body[r.body] = 1;
  for (size_t i = 0; i < nb; ++i)
    for (int k = m.body_point_begin[i]; k < m.body_point_end[i]; ++k)
      if (rim_body[i] && rim_of[k] < 0) return "a wheel body has points off its rims";
  for (int s : m.loose_springs)
    if (rim_of[m.springs[s].a] >= 0 || rim_of[m.springs[s].b] >= 0) return "a rim point has a spring off its fans";
  for (const Rim& r : P->rims)
    for (int f = 0; f < r.nf; ++f)
      if (rim_of[r.b[f]] >= 0) return "a fan ends on a rim point";
  // plain points: every point of the other bodies, in body order
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
  for (Rim& r : P->rims)
    for (int f = 0; f < r.nf; ++f) r.b[f] = plain_of[r.b[f]];
  // rims by body, then first point: the general path's contact order
  std::stable_sort(P->rims.begin(), P->rims.end(),
                   [](const Rim& a, const Rim& b) { return a.body != b.body ? a.body < b.body : a.a0 < b.a0; });
  P->rim_begin.assign(nb, 0);
  P->rim_end.assign(nb, 0);
  for (size_t i = 0, r = 0; i < nb; ++i) {
    P->rim_begin[i] = static_cast<int>(r);
    while (r < P->rims.size() && P->rims[r].body == static_cast<int>(i)) ++r;
    P->rim_end[i] = static_cast<int>(r);
  }
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
  for (int s : m.loose_springs) {
    const Spring& sp = m.springs[s];
    P->loose.push_back({plain_of[sp.a], plain_of[sp.b], sp.stiffness, sp.damping, sp.rest_length, sp.isotropic});
  }
  for (const Wheel& w : m.wheels) P->wheels.push_back({w.body, w.carrier, w.axis.x(), w.axis.y(), w.axis.z()});
  for (size_t i = 0; i < nb; ++i) P->rigid.bodies.push_back(bodyConstants(m.bodies[i]));
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
  return nullptr;
}

struct PlainL {
  double r[3], p[3], u[3], f[3];
};
// A point below the plane, as velocity_constraints.cpp's Contact.
struct ContactR {
  int body, point, wheel;
  double p[3], r[3], u[3], depth, N, mu;
  double a1[3], a2[3], b1[3], b2[3], k00, k01, k11, i00, i01, i10, i11, j0, j1;
};

struct Scratch {
  explicit Scratch(const Plan& P, const Model& m)
      : rigid(P.rigid), plain(P.plain.size()) {
    for (auto* v : {&H, &fx, &fy, &fz, &gx, &gy, &gz}) v->assign(static_cast<size_t>(P.max_rim), 0.0);
    con.resize(m.contact_points.size());
  }
  fastcar::Scratch<double> rigid;  // bodies: R, Iw, w, F, T, vp, wp
  std::vector<PlainL> plain;
  std::vector<double> H;           // one rim's H at each point
  std::vector<double> fx, fy, fz;  // its spring force on each point (wheel frame)
  std::vector<double> gx, gy, gz;  // of which the first fan's
  std::vector<ContactR> con;  // every contact point once at most; [0, ncon) this evaluation's
  size_t ncon = 0;
  std::span<ContactR> contacts() { return {con.data(), ncon}; }
  double axis[kMaxWheels][3];  // wheel axes, world
  double brake_impulse[kMaxWheels];
  double drive_power = 0.0, max_depth = 0.0;
  int sweeps = 0;
};

using fastcar::cross3;
using fastcar::dot3;
using fastcar::mat3vec;

GROUNDSIM_INLINE_BODY void addContact(const Model& m, const Plan& P, Scratch& S, int body, int point, int wheel,
                                      double H, const double* p, const double* r, const double* u) {
  ContactR& c = S.con[S.ncon++];  // every field below is set before it is read
  c.body = body;
  c.point = point;
  c.wheel = wheel;
  for (int d = 0; d < 3; ++d) {
    c.p[d] = p[d];
    c.r[d] = r[d];
    c.u[d] = u[d];
  }
  c.depth = -H / P.gn;
  c.mu = m.ground->friction(Vec3(p[0], p[1], p[2]), P.scene_mu);
  c.j0 = c.j1 = 0.0;
}

// One rim: its two fans, the plane's H and the sums into the wheel body
// and the fans' far points, in one pass over its points. The pass runs in
// the wheel's frame, where a rim point sits still at l: the spring vector
// is R^T (b - c) - l and the relative velocity R^T (u_b - v) - Omega x l
// (Omega = R^T omega), lengths and rates are the same in every frame, and
// the sums go back to the world frame once per rim. No point's world
// position or velocity is formed.
using v4d = fastcar::v4d;
GROUNDSIM_INLINE_BODY v4d load4(const double* p) {
  v4d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
GROUNDSIM_INLINE_BODY double sum4(v4d v) { return (v[0] + v[1]) + (v[2] + v[3]); }

GROUNDSIM_INLINE_BODY void rimPass(const Plan& P, const Rim& rim, const double* y, BodyL<double>& B, Scratch& S) {
  const double* R = B.R;
  // R^T x for a world vector x
  auto back = [R](double x, double yy, double z, double* o) {
    o[0] = R[0] * x + R[3] * yy + R[6] * z;
    o[1] = R[1] * x + R[4] * yy + R[7] * z;
    o[2] = R[2] * x + R[5] * yy + R[8] * z;
  };
  PlainL& b0 = S.plain[rim.b[0]];
  PlainL& b1 = S.plain[rim.b[1]];
  double be0[3], ge0[3], be1[3], ge1[3], Om[3], nu[3];
  back(b0.p[0] - y[0], b0.p[1] - y[1], b0.p[2] - y[2], be0);
  back(b0.u[0] - y[7], b0.u[1] - y[8], b0.u[2] - y[9], ge0);
  back(b1.p[0] - y[0], b1.p[1] - y[1], b1.p[2] - y[2], be1);
  back(b1.u[0] - y[7], b1.u[1] - y[8], b1.u[2] - y[9], ge1);
  back(B.w[0], B.w[1], B.w[2], Om);
  back(P.n[0], P.n[1], P.n[2], nu);
  const double H0 = P.n[0] * y[0] + P.n[1] * y[1] + P.n[2] * y[2] - P.offset;
  const double b0x = be0[0], b0y = be0[1], b0z = be0[2], e0x = ge0[0], e0y = ge0[1], e0z = ge0[2];
  const double b1x = be1[0], b1y = be1[1], b1z = be1[2], e1x = ge1[0], e1y = ge1[1], e1z = ge1[2];
  const double Ox = Om[0], Oy = Om[1], Oz = Om[2], nx = nu[0], ny = nu[1], nz = nu[2];
  const double* __restrict lx = rim.lx.data();
  const double* __restrict ly = rim.ly.data();
  const double* __restrict lz = rim.lz.data();
  const double* __restrict k0 = rim.k[0].data();
  const double* __restrict c0 = rim.c[0].data();
  const double* __restrict s0 = rim.rest[0].data();
  const double* __restrict k1 = rim.k[1].data();
  const double* __restrict c1 = rim.c[1].data();
  const double* __restrict s1 = rim.rest[1].data();
  double* __restrict H = S.H.data();
  double* __restrict fxs = S.fx.data();
  double* __restrict fys = S.fy.data();
  double* __restrict fzs = S.fz.data();
  double* __restrict gxs = S.gx.data();
  double* __restrict gys = S.gy.data();
  double* __restrict gzs = S.gz.data();
  const int n = rim.padded;
  // per point, no reduction (GCC keeps `omp simd` reductions in memory):
  // the sums follow 4 wide
#pragma omp simd
  for (int q = 0; q < n; ++q) {
    const double px = lx[q], py = ly[q], pz = lz[q];
    const double ux = Oy * pz - Oz * py, uy = Oz * px - Ox * pz, uz = Ox * py - Oy * px;
    // springs.cpp's fan formula (pointwise.hpp); the tiny floor keeps
    // 1/len finite at zero length, where the guard gives no force
    const double dx = b0x - px, dy = b0y - py, dz = b0z - pz;
    const double len2 = dx * dx + dy * dy + dz * dz;
    const double inv = 1.0 / std::sqrt(len2 + 1e-300);
    const double t =
        pointwise::springTensionFan(len2, inv, dx * (e0x - ux) + dy * (e0y - uy) + dz * (e0z - uz), k0[q], c0[q], s0[q]);
    const double gx = b1x - px, gy = b1y - py, gz = b1z - pz;
    const double m2 = gx * gx + gy * gy + gz * gz;
    const double iv = 1.0 / std::sqrt(m2 + 1e-300);
    const double t1 =
        pointwise::springTensionFan(m2, iv, gx * (e1x - ux) + gy * (e1y - uy) + gz * (e1z - uz), k1[q], c1[q], s1[q]);
    gxs[q] = t * dx;
    gys[q] = t * dy;
    gzs[q] = t * dz;
    fxs[q] = t * dx + t1 * gx;
    fys[q] = t * dy + t1 * gy;
    fzs[q] = t * dz + t1 * gz;
    H[q] = H0 + (nx * px + ny * py + nz * pz);
  }
  v4d Fx{}, Fy{}, Fz{}, Tx{}, Ty{}, Tz{}, Gx{}, Gy{}, Gz{};
  for (int q = 0; q < n; q += 4) {
    const v4d px = load4(lx + q), py = load4(ly + q), pz = load4(lz + q);
    const v4d fx = load4(fxs + q), fy = load4(fys + q), fz = load4(fzs + q);
    Fx += fx;
    Fy += fy;
    Fz += fz;
    Tx += py * fz - pz * fy;
    Ty += pz * fx - px * fz;
    Tz += px * fy - py * fx;
    Gx += load4(gxs + q);
    Gy += load4(gys + q);
    Gz += load4(gzs + q);
  }
  // the far points get the opposite: the first fan's sum, and the rest
  const double Fb[3] = {sum4(Fx), sum4(Fy), sum4(Fz)}, Tb[3] = {sum4(Tx), sum4(Ty), sum4(Tz)};
  const double G0[3] = {-sum4(Gx), -sum4(Gy), -sum4(Gz)};
  const double G1[3] = {-Fb[0] - G0[0], -Fb[1] - G0[1], -Fb[2] - G0[2]};
  double Fw[3], Tw[3], G0w[3], G1w[3];
  mat3vec(R, Fb, Fw);
  mat3vec(R, Tb, Tw);
  mat3vec(R, G0, G0w);
  mat3vec(R, G1, G1w);
  for (int d = 0; d < 3; ++d) {
    B.F[d] += Fw[d];
    B.T[d] += Tw[d];
    b0.f[d] += G0w[d];
    b1.f[d] += G1w[d];
  }
}

// The rim's points below the plane become contacts (their kinematics again:
// a handful of points, so the pass above stores none), found four at a time.
GROUNDSIM_INLINE_BODY void rimContacts(const Model& m, const Plan& P, const Rim& rim, const double* y,
                                       const BodyL<double>& B, Scratch& S) {
  for (int q0 = 0; q0 < rim.padded; q0 += 4) {
    const v4d h = load4(S.H.data() + q0);
    const auto below = h < 0.0;
    if (!((below[0] | below[1]) | (below[2] | below[3]))) continue;
    for (int q = q0; q < q0 + 4; ++q) {
      if (!(S.H[q] < 0.0) || !rim.contact[q]) continue;
      const double l[3] = {rim.lx[q], rim.ly[q], rim.lz[q]};
      double r[3], p[3], u[3], wr[3];
      mat3vec(B.R, l, r);
      cross3(B.w, r, wr);
      for (int d = 0; d < 3; ++d) {
        p[d] = y[d] + r[d];
        u[d] = y[7 + d] + wr[d];
      }
      addContact(m, P, S, rim.body, rim.a0 + q, rim.wheel, S.H[q], p, r, u);
    }
  }
}

// evaluate's phases, in its order.

// Each body's rotation, world inertia inverse, angular velocity, gravity.
GROUNDSIM_INLINE_BODY void bodyFrames(const Plan& P, const double* Y, Scratch& S) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  for (size_t i = 0; i < P.rigid.bodies.size(); ++i) {
    BodyL<double>& B = bodies[i];
    const double* y = Y + 13 * i;
    const double inq = 1.0 / std::sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6]);
    fastcar::quatToMat(y[3] * inq, y[4] * inq, y[5] * inq, y[6] * inq, B.R);
    fastcar::rotateInertia(B.R, P.rigid.bodies[i].Ib, B.Iw);
    mat3vec(B.Iw, y + 10, B.w);
    for (int d = 0; d < 3; ++d) {
      B.F[d] = P.rigid.bodies[i].mass * P.gravity[d];
      B.T[d] = 0.0;
    }
  }
}

// The plain (non-rim) points' arms, positions and velocities; a steered
// point turns about its body's vertical.
GROUNDSIM_INLINE_BODY void plainPoints(const Plan& P, const double* Y, const std::vector<WheelControl>& ctl,
                                       Scratch& S) {
  for (size_t k = 0; k < P.plain.size(); ++k) {
    const PlainPoint& pc = P.plain[k];
    PlainL& pt = S.plain[k];
    const BodyL<double>& B = S.rigid.bodies[pc.body];
    const double* y = Y + 13 * pc.body;
    double l[3] = {pc.lx, pc.ly, pc.lz};
    if (pc.steer_wheel >= 0) {
      const double a = ctl[pc.steer_wheel].steer;
      const double c = a == 0.0 ? 1.0 : std::cos(a), s = a == 0.0 ? 0.0 : std::sin(a);
      l[0] = pc.pivx + c * pc.dx - s * pc.dy;
      l[1] = pc.pivy + s * pc.dx + c * pc.dy;
    }
    mat3vec(B.R, l, pt.r);
    double wr[3];
    cross3(B.w, pt.r, wr);
    for (int d = 0; d < 3; ++d) {
      pt.p[d] = y[d] + pt.r[d];
      pt.u[d] = y[7 + d] + wr[d];
      pt.f[d] = 0.0;
    }
  }
}

// Rims and contacts body by body: the general path's contact order.
GROUNDSIM_INLINE_BODY void rimsAndContacts(const Model& m, const Plan& P, const double* Y, Scratch& S) {
  S.ncon = 0;
  for (size_t i = 0; i < P.rigid.bodies.size(); ++i) {
    const double* y = Y + 13 * i;
    for (int r = P.rim_begin[i]; r < P.rim_end[i]; ++r) {
      const Rim& rim = P.rims[r];
      rimPass(P, rim, y, S.rigid.bodies[i], S);
      rimContacts(m, P, rim, y, S.rigid.bodies[i], S);
    }
    for (int k = P.plain_begin[i]; k < P.plain_end[i]; ++k) {
      if (!P.plain[k].contact) continue;
      const PlainL& pt = S.plain[k];
      const double H = P.n[0] * pt.p[0] + P.n[1] * pt.p[1] + P.n[2] * pt.p[2] - P.offset;
      if (H < 0.0) addContact(m, P, S, static_cast<int>(i), P.plain[k].model_point, P.plain[k].wheel, H, pt.p, pt.r, pt.u);
    }
  }
}

// The springs between plain points (springs.cpp's applyOne).
GROUNDSIM_INLINE_BODY void looseSprings(const Plan& P, Scratch& S) {
  for (const LooseSpring& sp : P.loose) {
    PlainL& A = S.plain[sp.a];
    PlainL& Bp = S.plain[sp.b];
    double d[3], e[3], g[3];
    for (int k = 0; k < 3; ++k) {
      d[k] = Bp.p[k] - A.p[k];
      e[k] = Bp.u[k] - A.u[k];
    }
    if (sp.isotropic) {
      for (int k = 0; k < 3; ++k) g[k] = sp.k * d[k] + sp.c * e[k];
    } else {
      const double len2 = dot3(d, d);
      const double inv = 1.0 / std::sqrt(len2 + 1e-300);
      const double t = pointwise::springTension(len2, inv, dot3(d, e), sp.k, sp.c, sp.rest);
      for (int k = 0; k < 3; ++k) g[k] = t * d[k];
    }
    for (int k = 0; k < 3; ++k) {
      A.f[k] += g[k];
      Bp.f[k] -= g[k];
    }
  }
}

// The plain points' forces summed on their bodies.
GROUNDSIM_INLINE_BODY void pointSums(const Plan& P, Scratch& S) {
  for (size_t i = 0; i < P.rigid.bodies.size(); ++i) {
    BodyL<double>& B = S.rigid.bodies[i];
    for (int k = P.plain_begin[i]; k < P.plain_end[i]; ++k) {
      const PlainL& pt = S.plain[k];
      double rf[3];
      cross3(pt.r, pt.f, rf);
      for (int d = 0; d < 3; ++d) {
        B.F[d] += pt.f[d];
        B.T[d] += rf[d];
      }
    }
  }
}

// Normal forces (report eq. 10 with damping).
GROUNDSIM_INLINE_BODY void normalForces(const Plan& P, Scratch& S) {
  S.max_depth = 0.0;
  for (ContactR& c : S.contacts()) {
    const double rate = -(c.u[0] * P.cn[0] + c.u[1] * P.cn[1] + c.u[2] * P.cn[2]);
    c.N = pointwise::penaltyNormal(P.stiffness, c.depth, P.damping, rate, P.hunt_crossley);
    S.max_depth = std::max(S.max_depth, c.depth);
    BodyL<double>& B = S.rigid.bodies[c.body];
    const double f[3] = {c.N * P.cn[0], c.N * P.cn[1], c.N * P.cn[2]};
    double rf[3];
    cross3(c.r, f, rf);
    for (int d = 0; d < 3; ++d) {
      B.F[d] += f[d];
      B.T[d] += rf[d];
    }
  }
}

// Drive torque about each axle, its reaction on the carrier; whether any
// wheel brakes.
GROUNDSIM_INLINE_BODY bool driveTorques(const Plan& P, const std::vector<WheelControl>& ctl, Scratch& S) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  S.drive_power = 0.0;
  bool braking = false;
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const WheelC& wc = P.wheels[w];
    BodyL<double>& B = bodies[wc.body];
    const double ax[3] = {wc.ax, wc.ay, wc.az};
    mat3vec(B.R, ax, S.axis[w]);
    const double* a = S.axis[w];
    braking = braking || ctl[w].brake_torque > 0.0;
    const double Tq = ctl[w].drive_torque;
    if (Tq == 0.0) continue;
    for (int d = 0; d < 3; ++d) B.T[d] += Tq * a[d];
    if (wc.carrier < 0) {
      S.drive_power += Tq * dot3(a, B.w);
      continue;
    }
    BodyL<double>& C = bodies[wc.carrier];
    for (int d = 0; d < 3; ++d) C.T[d] -= Tq * a[d];
    const double rel[3] = {B.w[0] - C.w[0], B.w[1] - C.w[1], B.w[2] - C.w[2]};
    S.drive_power += Tq * dot3(a, rel);
  }
  return braking;
}

// The bodies' velocities after h under the forces so far (friction's start).
GROUNDSIM_INLINE_BODY void predictVelocities(const Plan& P, const double* Y, double h, Scratch& S) {
  for (size_t i = 0; i < P.rigid.bodies.size(); ++i) {
    BodyL<double>& B = S.rigid.bodies[i];
    const double* y = Y + 13 * i;
    double Lh[3];
    for (int d = 0; d < 3; ++d) {
      B.vp[d] = y[7 + d] + h * B.F[d] * P.rigid.bodies[i].inv_mass;
      Lh[d] = y[10 + d] + h * B.T[d];
    }
    mat3vec(B.Iw, Lh, B.wp);
  }
}

// Each contact's 2x2 tangential effective mass and its inverse; returns
// the impulses' scale for the convergence test.
GROUNDSIM_INLINE_BODY double contactMasses(const Plan& P, const std::vector<WheelControl>& ctl, double h,
                                           Scratch& S) {
  double scale = 0.0;
  for (ContactR& c : S.contacts()) {
    const BodyL<double>& B = S.rigid.bodies[c.body];
    const double inv_m = P.rigid.bodies[c.body].inv_mass;
    cross3(c.r, P.t1, c.a1);
    cross3(c.r, P.t2, c.a2);
    mat3vec(B.Iw, c.a1, c.b1);
    mat3vec(B.Iw, c.a2, c.b2);
    c.k01 = dot3(c.a1, c.b2);
    c.k00 = inv_m + dot3(c.a1, c.b1);
    c.k11 = inv_m + dot3(c.a2, c.b2);
    const double invdet = 1.0 / (c.k00 * c.k11 - c.k01 * c.k01);
    c.i00 = c.k11 * invdet;
    c.i01 = c.i10 = -c.k01 * invdet;
    c.i11 = c.k00 * invdet;
    scale += c.mu * c.N * h;
  }
  for (size_t w = 0; w < P.wheels.size(); ++w) scale += std::max(ctl[w].brake_torque, 0.0) * h;
  return scale;
}

// One sweep's brakes: each braked wheel's impulse about its axle, clamped
// to its torque times h, against its carrier. Adds to change and total.
GROUNDSIM_INLINE_BODY void brakeSweep(const Plan& P, const std::vector<WheelControl>& ctl, double h, Scratch& S,
                                      double& change, double& total) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const WheelC& wc = P.wheels[w];
    const double Bt = ctl[w].brake_torque;
    if (!(Bt > 0.0) || wc.carrier < 0) continue;
    BodyL<double>& B = bodies[wc.body];
    BodyL<double>& C = bodies[wc.carrier];
    const double* a = S.axis[w];
    double ia[3], ic[3];
    mat3vec(B.Iw, a, ia);
    mat3vec(C.Iw, a, ic);
    const double rel[3] = {B.wp[0] - C.wp[0], B.wp[1] - C.wp[1], B.wp[2] - C.wp[2]};
    const double acc = std::clamp(S.brake_impulse[w] - dot3(a, rel) / (dot3(a, ia) + dot3(a, ic)), -Bt * h, Bt * h);
    const double d = acc - S.brake_impulse[w];
    S.brake_impulse[w] = acc;
    change += std::abs(d);
    total += std::abs(acc);
    for (int k = 0; k < 3; ++k) {
      B.wp[k] += d * ia[k];
      C.wp[k] -= d * ic[k];
    }
  }
}

// One sweep's contacts: each contact's tangential impulse, inside its
// friction disc. Adds to change and total.
GROUNDSIM_INLINE_BODY void contactSweep(const Plan& P, double h, Scratch& S, double& change, double& total) {
  for (ContactR& c : S.contacts()) {
    BodyL<double>& B = S.rigid.bodies[c.body];
    const double ut0 = dot3(P.t1, B.vp) + dot3(B.wp, c.a1);
    const double ut1 = dot3(P.t2, B.vp) + dot3(B.wp, c.a2);
    double acc0 = c.j0 - (c.i00 * ut0 + c.i01 * ut1);
    double acc1 = c.j1 - (c.i10 * ut0 + c.i11 * ut1);
    const double limit = c.mu * c.N * h;
    const double an = std::sqrt(acc0 * acc0 + acc1 * acc1);
    if (an > limit) {
      // sliding: mu N opposite the slip this contact would have without
      // its own friction (velocity_constraints.cpp says why)
      const double free0 = ut0 - (c.k00 * c.j0 + c.k01 * c.j1);
      const double free1 = ut1 - (c.k01 * c.j0 + c.k11 * c.j1);
      const double fn = std::sqrt(free0 * free0 + free1 * free1);
      if (fn > 1e-12) {
        acc0 = -limit / fn * free0;
        acc1 = -limit / fn * free1;
      } else {
        acc0 *= limit / an;
        acc1 *= limit / an;
      }
    }
    const double d0 = acc0 - c.j0, d1 = acc1 - c.j1;
    c.j0 = acc0;
    c.j1 = acc1;
    change += std::abs(d0) + std::abs(d1);
    total += std::abs(acc0) + std::abs(acc1);
    const double inv_m = P.rigid.bodies[c.body].inv_mass;
    for (int q = 0; q < 3; ++q) {
      B.vp[q] += (d0 * P.t1[q] + d1 * P.t2[q]) * inv_m;
      B.wp[q] += d0 * c.b1[q] + d1 * c.b2[q];
    }
  }
}

// The brake and friction impulses as forces and torques over h.
GROUNDSIM_INLINE_BODY void impulsesAsForces(const Plan& P, double h, bool braking, Scratch& S) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  for (size_t w = 0; braking && w < P.wheels.size(); ++w) {
    const WheelC& wc = P.wheels[w];
    if (S.brake_impulse[w] == 0.0 || wc.carrier < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const double tq = S.brake_impulse[w] / h * S.axis[w][k];
      bodies[wc.body].T[k] += tq;
      bodies[wc.carrier].T[k] -= tq;
    }
  }
  for (const ContactR& c : S.contacts()) {
    BodyL<double>& B = bodies[c.body];
    double f[3], rf[3];
    for (int q = 0; q < 3; ++q) f[q] = (c.j0 * P.t1[q] + c.j1 * P.t2[q]) / h;
    cross3(c.r, f, rf);
    for (int q = 0; q < 3; ++q) {
      B.F[q] += f[q];
      B.T[q] += rf[q];
    }
  }
}

// Stick-slip friction and brakes (velocity_constraints.cpp): impulses that
// bring the contacts' slip and the braked wheels' spin to rest within h,
// bounded by mu N h and the brake torque times h, in sweeps until they settle.
GROUNDSIM_INLINE_BODY void frictionAndBrakes(const Plan& P, const double* Y, const std::vector<WheelControl>& ctl,
                                             double h, bool braking, Scratch& S) {
  S.sweeps = 0;
  for (size_t w = 0; w < P.wheels.size(); ++w) S.brake_impulse[w] = 0.0;
  if (S.ncon == 0 && !braking) return;
  predictVelocities(P, Y, h, S);
  const double scale = contactMasses(P, ctl, h, S);
  for (int iter = 0; iter < P.friction_iterations; ++iter) {
    double change = 0.0, total = 0.0;
    if (braking) brakeSweep(P, ctl, h, S, change, total);
    contactSweep(P, h, S, change, total);
    S.sweeps = iter + 1;
    if (pointwise::converged(change, total, scale)) break;
  }
  impulsesAsForces(P, h, braking, S);
}

// computeForces for this model (forces.cpp), ending with the friction and
// brake impulses turned into forces in the bodies' F and T.
GROUNDSIM_INLINE_BODY void evaluate(const Model& m, const Plan& P, const double* Y,
                                    const std::vector<WheelControl>& ctl, double h, Scratch& S) {
  bodyFrames(P, Y, S);
  plainPoints(P, Y, ctl, S);
  rimsAndContacts(m, P, Y, S);
  looseSprings(P, S);
  pointSums(P, S);
  normalForces(P, S);
  const bool braking = driveTorques(P, ctl, S);
  frictionAndBrakes(P, Y, ctl, h, braking, S);
}

// q (x y z w) turned by the rotation vector omega h (math.hpp's
// integrateRotation), as fast_car_kernel.hpp's turn but with the series'
// constant divisors as reciprocal products (a division by a constant that
// is not a power of two stays a division: ten of them per body and step).
GROUNDSIM_INLINE_BODY void turn(const double* q, const double* omega, double h, double* out, bool normalise) {
  const double wx = omega[0] * h, wy = omega[1] * h, wz = omega[2] * h;
  const double a2 = wx * wx + wy * wy + wz * wz;
  double c, s;
  if (a2 < pointwise::kRotationSeries) {
    pointwise::halfAngleSeries(a2, c, s);
  } else {
    const double angle = std::sqrt(a2), ha = 0.5 * angle;
    c = std::cos(ha);
    s = std::sin(ha) / angle;
  }
  const double dx = s * wx, dy = s * wy, dz = s * wz;
  const double bx = q[0], by = q[1], bz = q[2], bw = q[3];
  const double rw = c * bw - dx * bx - dy * by - dz * bz;
  const double rx = c * bx + dx * bw + dy * bz - dz * by;
  const double ry = c * by + dy * bw + dz * bx - dx * bz;
  const double rz = c * bz + dz * bw + dx * by - dy * bx;
  const double inv = normalise ? 1.0 / std::sqrt(rx * rx + ry * ry + rz * rz + rw * rw) : 1.0;
  out[0] = rx * inv;
  out[1] = ry * inv;
  out[2] = rz * inv;
  out[3] = rw * inv;
}

// Semi-implicit Euler (semi_implicit_euler.cpp): momenta, positions, the
// midpoint rotation with one pass.
GROUNDSIM_INLINE_BODY void integrate(const Plan& P, double* Y, double h, Scratch& S) {
  for (size_t i = 0; i < P.rigid.bodies.size(); ++i) {
    const FastCarPlan::BodyC& bc = P.rigid.bodies[i];
    BodyL<double>& B = S.rigid.bodies[i];
    double* y = Y + 13 * i;
    for (int d = 0; d < 3; ++d) {
      y[7 + d] += h * B.F[d] * bc.inv_mass;
      y[10 + d] += h * B.T[d];
      y[d] += h * y[7 + d];
    }
    double w0[3], Rm[9], w[3], qm[4];
    const double q0[4] = {y[3], y[4], y[5], y[6]};
    mat3vec(B.Iw, y + 10, w0);
    turn(q0, w0, 0.5 * h, qm, false);
    fastcar::quatToMat(qm[0], qm[1], qm[2], qm[3], Rm);
    fastcar::spinOf(Rm, bc.Ib, y + 10, w);
    turn(q0, w, h, y + 3, true);
  }
}

GROUNDSIM_WIDE void advanceWide(const Model& m, const Plan& P, double* y, const std::vector<WheelControl>& ctl,
                                double h, Scratch& S) {
  evaluate(m, P, y, ctl, h, S);
  integrate(P, y, h, S);
}
void advanceGeneric(const Model& m, const Plan& P, double* y, const std::vector<WheelControl>& ctl, double h,
                    Scratch& S) {
  evaluate(m, P, y, ctl, h, S);
  integrate(P, y, h, S);
}

}  // namespace

const char* ringCarUnsupported(const Model& m) {
  Plan P;
  return buildPlan(m, &P);
}

struct RingCar::Impl {
  Impl(const Model& m, Plan p) : plan(std::move(p)), scratch(plan, m), y_eval(m.stateSize()), applied(m.wheels.size()) {}
  Plan plan;
  Scratch scratch;
  Eigen::VectorXd y_eval;               // the configuration of the last evaluation
  std::vector<WheelControl> applied;    // and its controls
  double h = 0.0;                       // and its step
  int substeps = 1;                     // one: the configuration is the workspace's rollback copy
};

RingCar::RingCar(const Model& m) {
  Plan P;
  if (const char* why = buildPlan(m, &P)) throw std::invalid_argument(std::string("ring car: ") + why);
  impl_ = std::make_unique<Impl>(m, std::move(P));
}
RingCar::~RingCar() = default;

void RingCar::step(const Model& m, State& s, Workspace& ws) {
  Impl& I = *impl_;
  const int n = std::max(1, m.opt.substeps);
  const double h = m.opt.dt / n;
  const bool wide = useWideSimd(m);
  double* y = s.y.data();
  for (int k = 0; k < n; ++k) {
    // one substep: the rollback copy (Simulator::step) holds the configuration already
    if (k + 1 == n && n > 1) I.y_eval = s.y;  // same size: no allocation
    if (wide) advanceWide(m, I.plan, y, s.applied, h, I.scratch);
    else advanceGeneric(m, I.plan, y, s.applied, h, I.scratch);
    s.drive_work += h * I.scratch.drive_power;
  }
  I.applied = s.applied;
  I.h = h;
  I.substeps = n;
  ws.max_depth = I.scratch.max_depth;
  ws.friction_sweeps = I.scratch.sweeps;
}

void RingCar::exportTo(const Model& m, Workspace& ws) const {
  computeForces(m, impl_->substeps > 1 ? impl_->y_eval : ws.last_good.y, impl_->applied, impl_->h, ws);
}

}  // namespace groundsim
