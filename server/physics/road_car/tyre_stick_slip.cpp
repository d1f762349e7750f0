// The rigid stick-slip tyre: the report car's velocity-level Coulomb
// contact (velocity_constraints.cpp) at a road car's contact patches.
//
// Unknowns: per wheel the patch impulse (lambda_x, lambda_y) in the tyre
// frame and the brake impulse beta about the axle, 12 in all. Each moves
// the body (through the reduced mass matrix M of road_car.hpp, so the
// wheels' strut motion is included), the carriers along their struts and
// the wheel's spin; the velocities they act on are each patch's slip at
// the end of the step and each wheel's spin. W (12x12) maps impulses to
// those velocities; it is built once per evaluation from 12 solves with M.
//
// A wheel's tyre and brake are solved together as one 3x3 block: the tyre's
// grip and the brake both act on the spin, and apart they are so strongly
// coupled (a wheel's spin inertia I / r^2 ~ 10 kg against the car's
// ~400 kg per wheel) that Gauss-Seidel between them would contract by only
// ~1 - 1/40 per sweep. Blocks are swept wheel by wheel until the impulses
// stop changing; the body couples them weakly.
//
// Like the report's stick-slip friction this is sized by the step h, so
// only the time-stepping integrators take it (scene_builder.cpp refuses the
// others at /vehicles/i/tyres/model).
#include "physics/road_car/tyre_stick_slip.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace groundsim {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

struct Ctx {
  const RoadCarParams& p;
  const StickSlipBody& body;
  const std::array<StickSlipWheel, 4>& wheels;
};

// The 12 velocities (per wheel: patch slip x, y and spin) from a change of
// the body's twist (dv, dw), the struts' rates dsd and the spins dom.
Vec12 velocities(const Ctx& c, const Vec3& dv, const Vec3& dw, const double dsd[4], const double dom[4]) {
  Vec12 u = Vec12::Zero();
  for (int j = 0; j < 4; ++j) {
    const StickSlipWheel& w = c.wheels[j];
    if (!w.active) continue;
    u[3 * j + 2] = dom[j];
    if (!w.contact) continue;
    const Vec3 vel = dv + dw.cross(w.r_c) + dsd[j] * c.body.nb;
    u[3 * j] = vel.dot(w.tx) - dom[j] * c.p.wheel_radius;
    u[3 * j + 1] = vel.dot(w.ty);
  }
  return u;
}

// What force F at wheel k's patch adds to the body's generalised force and
// to the carrier's along-strut force (forces/road_cars.cpp's assembly, linear in F:
// the part along the strut moves the carrier, the moment about the hub
// along the axle goes to the wheel's spin, not the body).
void patchForce(const Ctx& c, const StickSlipWheel& w, const Vec3& F, Vec6& dG, double* dQ) {
  const Vec3& nb = c.body.nb;
  const double fn = F.dot(nb);
  const double m_geo = (w.r_c - w.r_hub).cross(F).dot(w.axle);
  dG.head<3>() += F - fn * nb;
  dG.tail<3>() += w.r_c.cross(F) - m_geo * w.axle - fn * w.r_hub.cross(nb);
  *dQ += fn;
}

// Velocities from impulse column col (wheel col / 3; 0, 1: patch x, y; 2: brake).
Vec12 response(const Ctx& c, const Eigen::LLT<Eigen::Matrix<double, 6, 6>>& llt, int col) {
  const int k = col / 3, kind = col % 3;
  const StickSlipWheel& w = c.wheels[k];
  const double I = c.p.wheel_inertia, r = c.p.wheel_radius, mu = c.p.wheel_mass;
  Vec6 dG = Vec6::Zero();
  double dQ[4] = {0, 0, 0, 0}, dom[4] = {0, 0, 0, 0};
  if (kind < 2) {
    const Vec3 t = kind == 0 ? w.tx : w.ty;
    patchForce(c, w, t, dG, &dQ[k]);
    dom[k] = kind == 0 ? -r / I : 0.0;  // the patch force's moment -F_x r on the spin
  } else {
    dG.tail<3>() = -w.axle;  // the brake's reaction on the body
    dom[k] = 1.0 / I;
  }
  const Vec6 a = llt.solve(dG);
  const Vec3 dv = a.head<3>(), dw = a.tail<3>();
  double dsd[4];
  for (int j = 0; j < 4; ++j) dsd[j] = dQ[j] / mu - (c.body.nb.dot(dv) + c.wheels[j].r_hub.cross(c.body.nb).dot(dw));
  return velocities(c, dv, dw, dsd, dom);
}

// Sliding at radius R: the impulse on the circle |lambda| = R whose slip
// after it, w + K lambda, points opposite it (Coulomb's maximal
// dissipation): lambda = -(K + m I)^-1 w with m >= 0 set by |lambda| = R
// (Newton on 1 / |lambda(m)| - 1 / R, which converges from m = 0 without
// overshoot). Opposing the slip before friction instead would be wrong
// wherever the patch's effective mass is anisotropic: a free wheel's spin
// gives the longitudinal direction ~10 kg against ~400 kg laterally, and a
// lateral slide would drag the wheel's spin back and forth every step.
Eigen::Vector2d slideImpulse(const Eigen::Matrix2d& K, const Eigen::Vector2d& w, double R) {
  if (!(R > 0.0)) return Eigen::Vector2d::Zero();  // no load: no friction (and no 1 / R)
  const Eigen::Vector2d stick = -K.inverse() * w;
  if (stick.norm() <= R) return stick;
  double m = 0.0;
  Eigen::Vector2d lam = stick;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Matrix2d A_inv = (K + m * Eigen::Matrix2d::Identity()).inverse();
    lam = -A_inv * w;
    const double n = lam.norm();
    if (std::abs(n - R) <= 1e-12 * R) break;
    const double dn = lam.dot(-A_inv * lam) / n;  // d|lambda| / dm < 0
    m = std::max(0.0, m + (1.0 / n - 1.0 / R) * n * n / dn);
  }
  return lam * (R / lam.norm());
}

// Wheel j's block: its impulses x (lambda_x, lambda_y, beta) given u_ex, the
// velocities with its own impulses removed. Stick if the impulse that stops
// the patch is within mu_static N h; else slide at mu_sliding N h opposite
// the slip (slideImpulse), the brake then holding what it can.
Eigen::Vector3d solveBlock(const StickSlipWheel& w, const Eigen::Matrix3d& K, const Eigen::Matrix3d& K_inv,
                           const Eigen::Vector3d& u_ex, const Eigen::Vector3d& x_old, double h, bool* sliding) {
  const double bmax = w.brake_cap * h;
  const bool brake = bmax > 0.0;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  *sliding = false;
  auto brakeFor = [&](const Eigen::Vector2d& lam) {  // stops the spin, within the brake's capacity
    return brake ? std::clamp(-(u_ex[2] + K.row(2).head<2>().dot(lam)) / K(2, 2), -bmax, bmax) : 0.0;
  };
  if (!w.contact) {
    x[2] = brakeFor(Eigen::Vector2d::Zero());
    return x;
  }
  const Eigen::Matrix2d Kxy = K.topLeftCorner<2, 2>();
  // stick: patch and (if braked) spin stopped
  Eigen::Vector2d lam;
  double beta = 0.0;
  if (brake) {
    x = -K_inv * u_ex;
    beta = x[2];
  }
  if (!brake || std::abs(beta) > bmax) {
    beta = brake ? std::clamp(beta, -bmax, bmax) : 0.0;
    lam = -Kxy.inverse() * (u_ex.head<2>() + K.topRightCorner<2, 1>() * beta);
  } else {
    lam = x.head<2>();
  }
  if (lam.norm() <= w.mu_static * w.normal * h) return Eigen::Vector3d(lam.x(), lam.y(), beta);
  // slide: the direction depends on the brake and the brake on the force
  *sliding = true;
  const double slide = w.mu_sliding * w.normal * h;
  beta = brake ? std::clamp(x_old[2], -bmax, bmax) : 0.0;
  for (int it = 0; it < 20; ++it) {
    lam = slideImpulse(Kxy, u_ex.head<2>() + K.topRightCorner<2, 1>() * beta, slide);
    const double next = brakeFor(lam);
    const bool settled = std::abs(next - beta) <= 1e-12 * (bmax + slide);
    beta = next;
    if (settled || !brake) break;
  }
  return Eigen::Vector3d(lam.x(), lam.y(), beta);
}

}  // namespace

void solveStickSlipTyres(const RoadCarParams& p, const StickSlipBody& body, double h,
                         std::array<StickSlipWheel, 4>& wheels) {
  bool any = false;
  for (const StickSlipWheel& w : wheels) any = any || w.active;
  if (!any) return;
  const Ctx c{p, body, wheels};
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(*body.M);

  // velocities at the end of the step with no stick-slip impulse
  const Vec6 a0 = llt.solve(*body.G);
  double sd[4], om[4];
  for (int j = 0; j < 4; ++j) {
    const StickSlipWheel& w = wheels[j];
    sd[j] = w.strut_rate + h * (body.Q[j] / p.wheel_mass -
                                (body.nb.dot(a0.head<3>()) + w.r_hub.cross(body.nb).dot(a0.tail<3>())));
    om[j] = w.spin + h * w.spin_rate;
  }
  Vec12 u = velocities(c, body.v + h * a0.head<3>(), body.omega + h * (a0.tail<3>() + body.gyro), sd, om);

  Mat12 W = Mat12::Zero();
  for (int col = 0; col < 12; ++col)
    if (wheels[col / 3].active) W.col(col) = response(c, llt, col);

  std::array<Eigen::Matrix3d, 4> K, K_inv;
  double scale = 0.0;
  for (int j = 0; j < 4; ++j) {
    if (!wheels[j].active) continue;
    K[j] = W.block<3, 3>(3 * j, 3 * j);
    if (wheels[j].contact) K_inv[j] = K[j].inverse();
    scale += (wheels[j].mu_static * wheels[j].normal + wheels[j].brake_cap) * h;
  }

  Vec12 x = Vec12::Zero();
  bool sliding[4] = {false, false, false, false};
  for (int iter = 0; iter < 200; ++iter) {
    double change = 0.0, total = 0.0;
    for (int j = 0; j < 4; ++j) {
      if (!wheels[j].active) continue;
      const Eigen::Vector3d x_old = x.segment<3>(3 * j);
      const Eigen::Vector3d u_ex = u.segment<3>(3 * j) - K[j] * x_old;
      const Eigen::Vector3d x_new = solveBlock(wheels[j], K[j], K_inv[j], u_ex, x_old, h, &sliding[j]);
      const Eigen::Vector3d d = x_new - x_old;
      total += x_new.lpNorm<1>();
      if (d.isZero(0.0)) continue;
      u.noalias() += W.middleCols<3>(3 * j) * d;
      x.segment<3>(3 * j) = x_new;
      change += d.lpNorm<1>();
    }
    // converged: what is left cannot add up to creep
    if (change <= 1e-10 * total + 1e-13 * scale) break;
  }

  for (int j = 0; j < 4; ++j) {
    StickSlipWheel& w = wheels[j];
    if (!w.active) continue;
    w.fx = x[3 * j] / h;
    w.fy = x[3 * j + 1] / h;
    w.brake_torque = x[3 * j + 2] / h;
    w.sliding = sliding[j];
    Vec6 dG = Vec6::Zero();
    if (w.contact) patchForce(c, w, w.fx * w.tx + w.fy * w.ty, dG, &body.Q[j]);
    dG.tail<3>() -= w.brake_torque * w.axle;
    *body.G += dG;
  }
}

void stickSlipPatch(const TyreParams& t, double Fz, double mu_ground, const Vec3& r_c, RoadWheelOut& o,
                    StickSlipWheel& ss) {
  ss.contact = true;
  ss.tx = o.tx;
  ss.ty = o.ty;
  ss.r_c = r_c;
  ss.normal = Fz;
  ss.mu_static = mu_ground * t.friction_scale;
  ss.mu_sliding = ss.mu_static * t.sliding_ratio;
  o.fx = o.fy = 0.0;
  o.hold = 0.0;
}

void stickSlipWheel(const RoadCarParams& p, bool handbrake, double vx, double spin, double strut_rate,
                    const Vec3& r_hub, const Vec3& axle, double brake_cap, double t_rr, StickSlipWheel& ss,
                    double* t_drive) {
  const BrakeParams& bp = p.brakes;
  const double grip = ss.mu_static * ss.normal * p.wheel_radius;  // N m: the patch's most before sliding
  // a patch that slides (it let go last step) returns only mu_sliding N r:
  // a wheel braked or driven at the grip would then lock or spin for good,
  // so ABS releases the brake and traction control cuts the drive until the
  // wheel rolls with the road again
  const bool slipping = ss.contact && std::abs(vx - spin * p.wheel_radius) > 0.01 + 1e-3 * std::abs(vx);
  if (bp.traction_control && ss.contact && *t_drive > 0.0) *t_drive = slipping ? 0.0 : std::min(*t_drive, grip);
  // ABS holds brake and rolling resistance together at kAbsShare of the
  // grip: at the grip itself the load's pitch oscillation tips a patch over
  // the limit every few steps, and each slide costs a release
  if (bp.abs && !handbrake && ss.contact && std::abs(vx) > bp.abs_min_speed)
    brake_cap = slipping ? 0.0 : std::min(brake_cap, std::max(0.0, kAbsShare * grip - std::abs(t_rr)));
  ss.brake_cap = brake_cap;
  ss.spin = spin;
  ss.spin_rate = (*t_drive + t_rr) / p.wheel_inertia;
  ss.strut_rate = strut_rate;
  ss.r_hub = r_hub;
  ss.axle = axle;
}

void applyStickSlipTyres(const RoadCarParams& p, const StickSlipBody& body, double h,
                         std::array<StickSlipWheel, 4>& wheels, RoadCarOut& out, double* aux_dot) {
  solveStickSlipTyres(p, body, h, wheels);
  for (int j = 0; j < 4; ++j) {
    const StickSlipWheel& w = wheels[j];
    if (!w.active) continue;
    RoadWheelOut& o = out.wheel[j];
    o.fx = w.fx;
    o.fy = w.fy;
    o.force += w.fx * w.tx + w.fy * w.ty;
    o.brake_torque = w.brake_torque;
    aux_dot[5 * j + 2] += (w.brake_torque - w.fx * p.wheel_radius) / p.wheel_inertia;
  }
}

}  // namespace groundsim
