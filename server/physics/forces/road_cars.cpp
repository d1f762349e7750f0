// One evaluation of the road cars' forces (see road_car/road_car.hpp for the
// parts; road_car_phase.hpp for the hooks).
//
// The suspension is a prismatic joint solved analytically: each wheel
// carrier moves with the body except along the strut axis n (the body's
// z), where its travel s is a state. With the body's accelerations a (6)
// and the carrier's along-strut equation
//   m_u (n . a_hub + s'') = Q = F_tyre . n + m_u g . n - F_spring,
// eliminating s'' leaves the body with the 6x6 mass matrix
//   M_car - sum m_u J^T n n^T J   (J: body twist -> hub velocity),
// i.e. the whole car's mass and inertia less the wheels' motion along their
// struts. No stiff joint springs: the stiffest modes left are the tyre's
// vertical spring on the unsprung mass (~16 Hz) and the tyre's deflection
// spring on the wheel's spin inertia, both far below 1 / dt at dt = 2 ms.
#include <algorithm>
#include <cmath>

#include "physics/forces/road_car_phase.hpp"
#include "physics/road_car/steering.hpp"
#include "physics/road_car/tyre.hpp"
#include "physics/road_car/tyre_stick_slip.hpp"
#include "physics/simd/simd_path.hpp"
#include "physics/simd/vector_math.hpp"

namespace groundsim {
namespace {

double springForce(const RoadCar& rc, int w, double s, double sd, double s_other) {
  const SuspensionParams& sp = rc.p.suspension[w < 2 ? 0 : 1];
  double f = rc.preload[w] + rc.spring_rate[w] * s + rc.damper_rate[w] * sd;
  if (s > sp.bump_travel) f += sp.stop_stiffness * (s - sp.bump_travel);
  if (s < -sp.droop_travel) f += sp.stop_stiffness * (s + sp.droop_travel);
  f += sp.anti_roll * (s - s_other);
  return f;
}

void holdGrowth(double hold, double ux, double uy, double* dux, double* duy) {
  if (hold <= 0.0) return;
  if (*dux * ux > 0.0) *dux *= 1.0 - hold;
  if (*duy * uy > 0.0) *duy *= 1.0 - hold;
}

// (a x b) . c, as Eigen's a.cross(b).dot(c) computes it (the same products
// and sums in the same order), kept in registers: here GCC stored Eigen's
// cross product and reloaded it as a pair for the dot, a store-forwarding
// stall (about 7% of this loop's samples each, perf).
GROUNDSIM_INLINE_BODY double tripleProduct(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double x = a.y() * b.z() - a.z() * b.y();
  const double y = a.z() * b.x() - a.x() * b.z();
  const double z = a.x() * b.y() - a.y() * b.x();
  return x * c.x() + y * c.y() + z * c.z();
}

// v + om x r + s n: the velocity of a point r of a body, moving at s along
// n on it, the same way, written component by component (a Vec3 built of
// the three sums went through the stack as a pair: the same stall).
GROUNDSIM_INLINE_BODY void pointVelocity(const Vec3& v, const Vec3& om, const Vec3& r, double s, const Vec3& n,
                                         Vec3& out) {
  out.x() = v.x() + (om.y() * r.z() - om.z() * r.y()) + s * n.x();
  out.y() = v.y() + (om.z() * r.x() - om.x() * r.z()) + s * n.y();
  out.z() = v.z() + (om.x() * r.y() - om.y() * r.x()) + s * n.z();
}

// (v + om x r) . t: the velocity of a body's point r along t, the same way.
GROUNDSIM_INLINE_BODY double pointVelocityAlong(const Vec3& v, const Vec3& om, const Vec3& r, const Vec3& t) {
  const double x = v.x() + (om.y() * r.z() - om.z() * r.y());
  const double y = v.y() + (om.z() * r.x() - om.x() * r.z());
  const double z = v.z() + (om.x() * r.y() - om.y() * r.x());
  return x * t.x() + y * t.y() + z * t.z();
}

// Numbers of the model, named once.
constexpr double kRadPerRev = 2.0 * 3.14159265358979323846;  // rad per revolution (engine rpm)
constexpr double kTreadRelaxRate = 20.0;  // 1/s  a tread off the ground relaxes at this rate
constexpr double kSlipSpeedFloor = 0.5;   // m/s  slip ratio and slip angle divide by |vx| at least this
constexpr double kSpinSignSpeed = 0.1;    // m/s  rolling resistance turns with the rim speed's sign within this
constexpr double kFadeSpeed = 3.0;        // m/s  the tread's low-speed damping fades out by this speed
constexpr double kTractionSlipFloor = 0.3;  // m/s  traction control allows at least this slip speed

// What one car's evaluation reads of its body and parameters, once.
struct CarBody {
  const RoadCar& rc;
  const RoadCarParams& p;
  const CarRuntime& in;
  RoadCarOut& out;
  int b, A;  // its body, the first of its wheels' states in y
  const Mat3& R;
  const Mat3& Ib;
  Vec3 nb, v, om_b, gyro;
  double r, I, mu_scene;
  // reciprocals: one division each per evaluation, multiplications per wheel
  double inv_r, inv_I, inv_h, inv_mu;
};

GROUNDSIM_INLINE_BODY CarBody carBody(const Model& m, const Workspace& ws, RoadCarOut& out, size_t c, double h) {
  const RoadCar& rc = m.road_cars[c];
  const RoadCarParams& p = rc.p;
  const int b = rc.body;
  const Mat3& R = ws.R[b];
  const Mat3& Ib = m.bodies[b].inertia;
  const Vec3 om_b = ws.omega[b];
  // I_w om as R (I_b (R^T om)): no R I_b R^T unless the stick-slip solve needs it
  const Vec3 Iw_om = R * (Ib * (R.transpose() * om_b)), gyro = om_b.cross(Iw_om);
  const double r = p.wheel_radius, I = p.wheel_inertia;
  return CarBody{rc, p, ws.car_inputs[c], out, b, m.auxBase() + rc.aux, R, Ib, R.col(2), ws.vel[b], om_b, gyro,
                 r, I, m.opt.contact.friction, 1.0 / r, 1.0 / I, 1.0 / h, 1.0 / p.wheel_mass};
}

// The powertrain: one engine for the driven wheels, split per axle by an
// open differential (equal halves per axle, applied in the spin pass).
GROUNDSIM_INLINE_BODY void powertrain(const CarBody& car, const Eigen::VectorXd& y, double axle_torque[2]) {
  const PowertrainParams& pt = car.p.powertrain;
  const bool fd = pt.drive != Drive::Rear, rd = pt.drive != Drive::Front;
  double wsum = 0.0;
  int nd = 0;
  for (int w = 0; w < 4; ++w)
    if ((w < 2 && fd) || (w >= 2 && rd)) {
      wsum += y[car.A + roadAux(w, 2)];
      ++nd;
    }
  const DriveOut drive = driveTorque(pt, car.in.gear, car.in.applied.throttle, nd ? wsum / nd : 0.0);
  car.out.engine_rpm = drive.engine_omega * 60.0 / kRadPerRev;
  axle_torque[0] = axle_torque[1] = 0.0;
  if (pt.drive == Drive::All) {
    axle_torque[0] = pt.front_share * drive.wheel_torque;
    axle_torque[1] = (1.0 - pt.front_share) * drive.wheel_torque;
  } else {
    axle_torque[pt.drive == Drive::Front ? 0 : 1] = drive.wheel_torque;
  }
}

// A wheel's contact patch, between the passes.
struct Patch {
  double s, sd, om, ux, uy, Fz, dux, duy, vx, vy;
  Vec3 r_hub, v_hub, axle, r_c, F;
};

// Three passes over the wheels, so that the transcendental functions of all
// four run together (vector_math.hpp): the patches, then the tyres' curves,
// slip angles and rolling resistance, then forces and torques.
struct WheelPasses {
  std::array<Patch, 4> pw;
  std::array<StickSlipWheel, 4> rigid{};  // stick-slip tyres: solved after the passes
  TyreLanes lanes;
  alignas(32) double spin_arg[4], slip_y[4], slip_x[4];
  alignas(32) double tyre_fx[4], tyre_fy[4], spin_tanh[4];
};

// Pass 1 for wheel w: where its hub is, whether it touches, the patch's
// frame and velocity, the vertical load; a slip tyre's lanes for pass 2.
GROUNDSIM_INLINE_BODY void contactPatch(const Model& m, const Eigen::VectorXd& y, const Workspace& ws,
                                        const CarBody& car, int w, double delta, WheelPasses& wp) {
  const TyreParams& tp = car.p.tyre[w < 2 ? 0 : 1];
  RoadWheelOut& o = car.out.wheel[w];
  StickSlipWheel& ss = wp.rigid[w];
  Patch& q = wp.pw[w];
  const double r = car.r;
  const Vec3& nb = car.nb;
  ss.active = !tp.slip_model;
  q.s = y[car.A + roadAux(w, 0)], q.sd = y[car.A + roadAux(w, 1)], q.om = y[car.A + roadAux(w, 2)];
  q.ux = y[car.A + roadAux(w, 3)], q.uy = y[car.A + roadAux(w, 4)];
  const Vec3 r_hub = car.R * car.rc.hub[w] + q.s * nb;
  q.r_hub = r_hub;
  const Vec3 p_hub = ws.com[car.b] + r_hub;
  pointVelocity(car.v, car.om_b, r_hub, q.sd, nb, q.v_hub);
  const double cd = delta == 0.0 ? 1.0 : std::cos(delta);  // straight ahead: no trig
  const double sn = delta == 0.0 ? 0.0 : std::sin(delta);
  q.axle = car.R * Vec3(-sn, cd, 0.0);
  Vec3 grad;
  const double H = m.ground->eval(p_hub, &grad);
  const double inv_gn = 1.0 / std::max(grad.norm(), 1e-12);
  const Vec3 n = grad * inv_gn;
  const double dist = H * inv_gn, pen = r - dist;
  q.F = Vec3::Zero();
  q.Fz = 0.0;
  q.r_c = r_hub - r * nb;
  o.contact = pen > 0.0;
  if (o.contact) {
    q.r_c = r_hub - dist * n;
    const Vec3 head = car.R * Vec3(cd, sn, 0.0);
    const Vec3 along = head - head.dot(n) * n;
    const double along2 = along.squaredNorm();
    o.tx = along2 > 0.0 ? Vec3(along * (1.0 / std::sqrt(along2))) : along;
    o.ty = n.cross(o.tx);
    Vec3 vc;
    pointVelocity(car.v, car.om_b, q.r_c, q.sd, nb, vc);
    q.vx = vc.dot(o.tx), q.vy = vc.dot(o.ty);
    q.Fz = std::max(0.0, tp.vertical_stiffness * pen - tp.vertical_damping * q.v_hub.dot(n));
    // the ground's friction at the patch (patches and maps, surface_friction.hpp)
    const double mu_ground = m.ground->friction(ws.com[car.b] + q.r_c, car.mu_scene);
    if (ss.active) {
      stickSlipPatch(tp, q.Fz, mu_ground, q.r_c, o, ss);
      q.F = q.Fz * n;
      q.dux = -kTreadRelaxRate * q.ux;  // unused: the tread has no deflection
      q.duy = -kTreadRelaxRate * q.uy;
    } else {
      deflectionRates(tp, q.vx, q.vy, q.om * r, q.ux, q.uy, &q.dux, &q.duy);
      TyreLanes& l = wp.lanes;
      l.on[w] = true;
      l.t[w] = &tp;
      l.Fz[w] = q.Fz;
      l.Fz0[w] = car.rc.nominal_load[w];
      l.inv_Fz0[w] = car.rc.inv_nominal_load[w];
      l.mu[w] = mu_ground;
      l.kx[w] = q.ux * tp.inv_relaxation;
      l.ky[w] = q.uy * tp.inv_relaxation;
      q.F = q.Fz * n;  // the tread's forces are added in pass 3
    }
  } else {
    o.hold = 0.0;
    q.dux = -kTreadRelaxRate * q.ux;  // off the ground the tread relaxes
    q.duy = -kTreadRelaxRate * q.uy;
    q.vx = q.vy = 0.0;
  }
  wp.spin_arg[w] = q.om * r / kSpinSignSpeed;
  wp.slip_y[w] = q.vy;
  wp.slip_x[w] = std::max(std::abs(q.vx), kSlipSpeedFloor);
}

// Pass 3, the tread: a slip tyre's forces from its curves, damped at low
// speed, held from winding up near standstill, capped by friction; the
// slip figures of any tyre in contact.
GROUNDSIM_INLINE_BODY void treadForces(const CarBody& car, int w, WheelPasses& wp, Patch& q) {
  const TyreParams& tp = car.p.tyre[w < 2 ? 0 : 1];
  RoadWheelOut& o = car.out.wheel[w];
  if (!o.contact) {
    o.fx = o.fy = o.slip_ratio = o.slip_vy = 0.0;
    o.slip_vx = 1.0;
    return;
  }
  if (!wp.rigid[w].active) {
    double Fx = wp.tyre_fx[w], Fy = wp.tyre_fy[w];
    // low-speed damping of the deflection springs (they would ring at standstill)
    const double fade = std::max(0.0, 1.0 - std::abs(q.vx) * (1.0 / kFadeSpeed));
    // near standstill a tread deflected past the peak slides instead of
    // stretching further: stop its growth (else a sliding stop winds up
    // a deflection that throws the car back once it halts)
    const double kxn = q.ux * tp.inv_relaxation * tp.inv_peak_slip_ratio;
    const double kyn = q.uy * tp.inv_relaxation * tp.inv_peak_slip_angle;
    o.hold = kxn * kxn + kyn * kyn > 1.0 ? fade : 0.0;
    holdGrowth(o.hold, q.ux, q.uy, &q.dux, &q.duy);
    Fx += tp.low_speed_damping * fade * q.dux;
    Fy += tp.low_speed_damping * fade * q.duy;
    // compared squared: the square root (its latency) only for a capped tread
    const double cap = wp.lanes.mu[w] * tp.friction_scale * q.Fz, mag2 = Fx * Fx + Fy * Fy;
    if (mag2 > cap * cap && mag2 > 0.0) {
      const double scale = cap / std::sqrt(mag2);
      Fx *= scale;
      Fy *= scale;
    }
    q.F = Fx * o.tx + Fy * o.ty + q.F;
    o.fx = Fx;
    o.fy = Fy;
  }
  o.slip_ratio = (q.om * car.r - q.vx) / std::max(std::abs(q.vx), kSlipSpeedFloor);
  o.slip_vy = wp.slip_y[w];
  o.slip_vx = wp.slip_x[w];
}

// The torques about a wheel's axle.
struct SpinTorques {
  double drive, brake, rolling, tyre, geometric;  // N m
};

// Pass 3, the spin: drive (with traction control), rolling resistance, the
// tyre's moment about the axle, then the brake (with ABS). The moment arm
// is the rolling radius r, the one the slip ratio uses: with the loaded
// radius the tyre would return more power to the car than the wheel gives
// it (by 1 - r_loaded / r, ~5%).
GROUNDSIM_INLINE_BODY SpinTorques spinTorques(const CarBody& car, int w, WheelPasses& wp, const Patch& q,
                                              const double axle_torque[2]) {
  const int ax = w < 2 ? 0 : 1;
  const TyreParams& tp = car.p.tyre[ax];
  const RoadWheelOut& o = car.out.wheel[w];
  StickSlipWheel& ss = wp.rigid[w];
  const double om = q.om, r = car.r, I = car.I;
  SpinTorques t{};
  t.geometric = tripleProduct(q.r_c - q.r_hub, q.F, q.axle);  // what the body does not get
  t.tyre = -(o.contact ? o.fx : 0.0) * r;
  t.rolling = -tp.rolling_resistance * q.Fz * r * wp.spin_tanh[w];
  double t_d = axle_torque[ax] * 0.5 + car.in.applied.wheel_torque[w];
  const double vx_c = o.contact ? pointVelocityAlong(car.v, car.om_b, q.r_c, o.tx) : 0.0;
  const double kp = tp.peak_slip_ratio;
  if (!ss.active && car.p.brakes.traction_control && o.contact && t_d > 0.0) {
    const double w_top = (vx_c + std::max(kp * std::abs(vx_c), kTractionSlipFloor)) * car.inv_r;
    t_d = std::min(t_d, std::max(0.0, I * (w_top - om) * car.inv_h - (t.rolling + t.tyre)));
  }
  const BrakeParams& bp = car.p.brakes;
  const bool hand = ax == 1 && car.in.applied.handbrake;
  const double cap = car.in.applied.brake * bp.max_torque * 0.5 * (ax == 0 ? bp.front_share : 1.0 - bp.front_share) +
                     (hand ? bp.handbrake_torque : 0.0);
  if (ss.active)
    stickSlipWheel(car.p, hand, vx_c, om, q.sd, q.r_hub, q.axle, cap, t.rolling, ss, &t_d);
  const double t_other = t_d + t.rolling + t.tyre;
  double t_b = ss.active ? 0.0 : std::clamp(-(I * om * car.inv_h + t_other), -cap, cap);  // stops the wheel within h at most
  if (!ss.active && bp.abs && !hand && o.contact && std::abs(vx_c) > bp.abs_min_speed) {
    const double lim = I * ((1.0 - kp) * vx_c * car.inv_r - om) * car.inv_h - t_other;
    t_b = vx_c > 0.0 ? std::max(t_b, std::min(0.0, lim)) : std::min(t_b, std::max(0.0, lim));
  }
  t.drive = t_d;
  t.brake = t_b;
  return t;
}

// The body's generalised force and (for stick-slip tyres) mass matrix.
struct BodySums {
  Eigen::Matrix<double, 6, 6> M;
  Eigen::Matrix<double, 6, 1> G;
  double Q[4];  // each strut's force on its wheel carrier
  bool rigid_tyres;
};

GROUNDSIM_INLINE_BODY void startSums(const Model& m, const Workspace& ws, const CarBody& car, BodySums& bs) {
  // the world-frame mass matrix only for the stick-slip tyres' solve; the
  // accelerations come from the body-frame inverse built once
  const RoadCarParams& p = car.p;
  bs.rigid_tyres = !p.tyre[0].slip_model || !p.tyre[1].slip_model;
  if (bs.rigid_tyres) {
    bs.M.setZero();
    bs.M.topLeftCorner<3, 3>() = m.bodies[car.b].mass * Mat3::Identity();
    bs.M.bottomRightCorner<3, 3>() = car.R * car.Ib * car.R.transpose();
  }
  bs.G.head<3>() = ws.body_force[car.b] - 0.5 * p.aero.air_density * p.aero.drag_area * car.v.norm() * car.v;
  bs.G.tail<3>() = ws.body_torque[car.b] - car.gyro;
}

// Pass 3, wheel w's outputs, its strut and its share of the body's sums and
// of the wheel states' rates.
GROUNDSIM_INLINE_BODY void wheelSums(const Model& m, const Eigen::VectorXd& y, Workspace& ws, const CarBody& car,
                                     int w, double delta, const Patch& q, const SpinTorques& t, BodySums& bs) {
  RoadWheelOut& o = car.out.wheel[w];
  const Vec3& nb = car.nb;
  o.r = q.r_c;
  o.drive_torque = t.drive;
  o.brake_torque = t.brake;
  o.normal = q.Fz;
  o.force = q.F;
  o.travel = q.s;
  o.steer = delta;
  const double s_other = y[car.A + roadAux(w ^ 1, 0)];
  bs.Q[w] = q.F.dot(nb) + car.p.wheel_mass * m.opt.gravity.dot(nb) - springForce(car.rc, w, q.s, q.sd, s_other);
  bs.G.head<3>() += q.F - bs.Q[w] * nb;
  bs.G.tail<3>() += q.r_c.cross(q.F) - (t.geometric + t.drive + t.brake) * q.axle - bs.Q[w] * q.r_hub.cross(nb);
  if (bs.rigid_tyres) {
    Eigen::Matrix<double, 6, 1> j;
    j << nb, q.r_hub.cross(nb);
    bs.M.noalias() -= car.p.wheel_mass * j * j.transpose();
  }
  double* d = ws.aux_dot.data() + car.rc.aux + 5 * w;
  d[0] = q.sd;
  d[2] = (t.drive + t.brake + t.rolling + t.tyre) * car.inv_I;
  d[3] = q.dux;
  d[4] = q.duy;
}

// The body's accelerations from its sums, M = T M_b T^T with T = diag(R, R)
// and M_b constant (road_car.hpp); each strut's travel acceleration.
GROUNDSIM_INLINE_BODY void bodyAccelerations(const Model& m, Workspace& ws, const CarBody& car, const BodySums& bs,
                                             const WheelPasses& wp) {
  const Mat3& R = car.R;
  Eigen::Matrix<double, 6, 1> Gb;
  Gb.head<3>().noalias() = R.transpose() * bs.G.head<3>();
  Gb.tail<3>().noalias() = R.transpose() * bs.G.tail<3>();
  const Eigen::Matrix<double, 6, 1> acc_b = car.rc.inv_mass_body * Gb;
  const Vec3 a_lin = R * acc_b.head<3>(), alpha = R * acc_b.tail<3>();
  ws.body_force[car.b] = m.bodies[car.b].mass * a_lin;
  ws.body_torque[car.b] = R * (car.Ib * acc_b.tail<3>()) + car.gyro;  // I_w alpha + om x I_w om
  for (int w = 0; w < 4; ++w)
    ws.aux_dot[car.rc.aux + 5 * w + 1] =
        bs.Q[w] * car.inv_mu - (car.nb.dot(a_lin) + tripleProduct(wp.pw[w].r_hub, car.nb, alpha));
}

// One car: the powertrain, steering, then the wheels' three passes, the
// stick-slip tyres' solve, and the body's accelerations.
GROUNDSIM_INLINE_BODY void roadCarBody(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws, size_t c,
                                       bool wide) {
  const CarBody car = carBody(m, ws, ws.road[c], c, h);
  double axle_torque[2];
  powertrain(car, y, axle_torque);
  double delta[4] = {0.0, 0.0, 0.0, 0.0};
  ackermannAngles(car.p.steering, car.p.wheelbase, car.p.track, car.in.steer_angle, &delta[0], &delta[1]);
  BodySums bs;
  startSums(m, ws, car, bs);
  WheelPasses wp;
  for (int w = 0; w < 4; ++w) contactPatch(m, y, ws, car, w, delta[w], wp);
  tyreForces4(wp.lanes, wide, wp.tyre_fx, wp.tyre_fy);
  tanh4(wp.spin_arg, wp.spin_tanh, wide);
  double drive_power = 0.0;
  for (int w = 0; w < 4; ++w) {
    Patch& q = wp.pw[w];
    treadForces(car, w, wp, q);
    const SpinTorques t = spinTorques(car, w, wp, q, axle_torque);
    drive_power += t.drive * q.om;
    wheelSums(m, y, ws, car, w, delta[w], q, t, bs);
  }
  // the stick-slip tyres' friction and brakes need the body's mass matrix
  if (bs.rigid_tyres) {
    const StickSlipBody sb{&bs.M, &bs.G, car.v, car.om_b, ws.inv_inertia_world[car.b] * car.gyro, car.nb, bs.Q};
    applyStickSlipTyres(car.p, sb, h, wp.rigid, car.out, ws.aux_dot.data() + car.rc.aux);
  }
  bodyAccelerations(m, ws, car, bs, wp);
  car.out.drive_power = drive_power;
  ws.drive_power += drive_power;
}

// applyRoadCars' body, built twice (simd_path.hpp): for the wide path (AVX2
// and FMA, with the tyres' functions from libmvec) and the generic one
GROUNDSIM_INLINE_BODY void roadCarsBody(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws,
                                        bool wide) {
  for (size_t c = 0; c < m.road_cars.size(); ++c) roadCarBody(m, y, h, ws, c, wide);
}

GROUNDSIM_WIDE void roadCarsWide(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  roadCarsBody(m, y, h, ws, true);
}
void roadCarsGeneric(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  roadCarsBody(m, y, h, ws, false);
}

}  // namespace

void applyRoadCars(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  if (useWideSimd(m.opt.deterministic)) roadCarsWide(m, y, h, ws);
  else roadCarsGeneric(m, y, h, ws);
}

void kickRoadCars(const Model& m, Eigen::VectorXd& y, const Workspace& ws, double k) {
  const int base = m.auxBase();
  for (const RoadCar& rc : m.road_cars)
    for (int w = 0; w < 4; ++w) {
      const int i = rc.aux + 5 * w;
      y[base + i + 1] += k * ws.aux_dot[i + 1];
      y[base + i + 2] += k * ws.aux_dot[i + 2];
    }
}

void driftRoadCars(const Model& m, Eigen::VectorXd& y, const Workspace& ws, double h) {
  const int base = m.auxBase();
  for (size_t c = 0; c < m.road_cars.size(); ++c) {
    const RoadCar& rc = m.road_cars[c];
    const int b = rc.body;
    // body velocities after the kick (angular from the new momentum)
    const Vec3 v = bodyVel(y, b), om_b = ws.inv_inertia_world[b] * bodyMom(y, b);
    for (int w = 0; w < 4; ++w) {
      const int i = base + rc.aux + 5 * w;
      const RoadWheelOut& o = ws.road[c].wheel[w];
      y[i] += h * y[i + 1];
      if (!o.contact || !rc.p.tyre[w < 2 ? 0 : 1].slip_model) {  // no deflection model to follow
        y[i + 3] += h * ws.aux_dot[i - base + 3];
        y[i + 4] += h * ws.aux_dot[i - base + 4];
        continue;
      }
      const Vec3 vc = v + om_b.cross(o.r);
      double dux, duy;
      deflectionRates(rc.p.tyre[w < 2 ? 0 : 1], vc.dot(o.tx), vc.dot(o.ty), y[i + 2] * rc.p.wheel_radius, y[i + 3],
                      y[i + 4], &dux, &duy);
      holdGrowth(o.hold, y[i + 3], y[i + 4], &dux, &duy);
      y[i + 3] += h * dux;
      y[i + 4] += h * duy;
    }
  }
}

}  // namespace groundsim
