#include "physics/kernels/ring_car.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <stdexcept>

#include "physics/base/pointwise.hpp"
#include "physics/kernels/fast_car_kernel.hpp"  // the rigid-body helpers shared with the circle-wheel car
#include "physics/kernels/ring_car_detail.hpp"
#include "physics/kernels/rigid_friction.hpp"
#include "physics/forces/forces.hpp"

namespace groundsim {

namespace {

// The plan and scratch (ring_car_detail.hpp) are built in ring_car_plan.cpp;
// the evaluation (friction and brakes: the shared rigid_friction.hpp), the
// integration and the wide and generic wrappers that inline them are here.
using ringcar::BodyL;
using ringcar::ContactR;
using ringcar::LooseSpring;
using ringcar::Plan;
using ringcar::PlainL;
using ringcar::PlainPoint;
using ringcar::Rim;
using ringcar::Scratch;
using ringcar::WheelC;
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
    c.rr[d] = r[d];
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

// The springs between plain points (the rigid paths' springBetween).
GROUNDSIM_INLINE_BODY void looseSprings(const Plan& P, Scratch& S) {
  for (const LooseSpring& sp : P.loose) fastcar::springBetween<double>(sp, S.plain[sp.a], S.plain[sp.b]);
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
    cross3(c.rr, f, rf);
    for (int d = 0; d < 3; ++d) {
      B.F[d] += f[d];
      B.T[d] += rf[d];
    }
  }
}

// Drive torque about each axle, its reaction on the carrier; each axle's
// world axis and brake torque for the friction solve.
GROUNDSIM_INLINE_BODY void driveTorques(const Plan& P, const std::vector<WheelControl>& ctl, Scratch& S) {
  std::vector<BodyL<double>>& bodies = S.rigid.bodies;
  S.drive_power = 0.0;
  for (size_t w = 0; w < P.wheels.size(); ++w) {
    const WheelC& wc = P.wheels[w];
    BodyL<double>& B = bodies[wc.body];
    const double ax[3] = {wc.ax, wc.ay, wc.az};
    mat3vec(B.R, ax, S.axles[w].a);
    const double* a = S.axles[w].a;
    S.brake[w] = ctl[w].brake_torque;
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
}

// The ring car's contacts as the shared friction solve reads them
// (rigid_friction.hpp): this evaluation's compacted list, a mu per contact;
// its wheels' axles for the brakes.
struct ContactList {
  const Plan& P;
  Scratch& S;
  size_t slots() const { return S.ncon; }
  bool solves(size_t) const { return true; }
  bool in(size_t) const { return true; }
  ContactR& at(size_t k) { return S.con[k]; }
  int body(size_t k) const { return S.con[k].body; }
  double mu(size_t k) const { return S.con[k].mu; }
  bool touching() const { return S.ncon > 0; }
  size_t axles() const { return P.wheels.size(); }
  int axleBody(size_t w) const { return P.wheels[w].body; }
  int axleCarrier(size_t w) const { return P.wheels[w].carrier; }
  ringcar::AxleR& axle(size_t w) { return S.axles[w]; }
};

// Stick-slip friction and brakes: the shared rigid solve over the list.
GROUNDSIM_INLINE_BODY void frictionAndBrakes(const Plan& P, const double* Y, double h, Scratch& S) {
  const rigid::FrictionInput<double> in{P.rigid.bodies.data(), S.rigid.bodies.data(), S.rigid.bodies.size(), Y,
                                        S.brake, P.t1, P.t2, h, P.friction_iterations};
  ContactList set{P, S};
  S.sweeps = rigid::frictionAndBrakes(in, set);
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
  driveTorques(P, ctl, S);
  frictionAndBrakes(P, Y, h, S);
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
    fastcar::turn(q0, w0, 0.5 * h, qm, false);  // the one rotation routine of the rigid paths
    fastcar::quatToMat(qm[0], qm[1], qm[2], qm[3], Rm);
    fastcar::spinOf(Rm, bc.Ib, y + 10, w);
    fastcar::turn(q0, w, h, y + 3, true);
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
  if (const char* why = ringcar::buildPlan(m, &P)) throw std::invalid_argument(std::string("ring car: ") + why);
  impl_ = std::make_unique<Impl>(m, std::move(P));
}
RingCar::~RingCar() = default;

void RingCar::step(const Model& m, State& s, Workspace& ws) {
  Impl& I = *impl_;
  const int n = std::max(1, m.opt.substeps);
  const double h = m.opt.dt / n;
  const bool wide = useWideSimd(m.opt.deterministic);
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
