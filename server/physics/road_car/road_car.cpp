// One evaluation of the road cars' forces (see road_car.hpp for the parts).
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

#include "physics/road_car/road_car_phase.hpp"
#include "physics/simd/simd_path.hpp"
#include "physics/road_car/steering.hpp"
#include "physics/road_car/tyre.hpp"
#include "physics/road_car/tyre_stick_slip.hpp"
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

}  // namespace

Eigen::Matrix<double, 6, 6> reducedMassBody(const RoadCar& rc, double mass, const Mat3& inertia) {
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  M.topLeftCorner<3, 3>() = mass * Mat3::Identity();
  M.bottomRightCorner<3, 3>() = inertia;
  for (int w = 0; w < 4; ++w) {
    Eigen::Matrix<double, 6, 1> j;
    j << Vec3::UnitZ(), rc.hub[w].cross(Vec3::UnitZ());
    M.noalias() -= rc.p.wheel_mass * j * j.transpose();
  }
  return M;
}

namespace {

// applyRoadCars' body, built twice (simd_path.hpp): for the wide path (AVX2
// and FMA, with the tyres' functions from libmvec) and the generic one
GROUNDSIM_INLINE_BODY void roadCarsBody(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws,
                                        bool wide) {
  const int base = m.auxBase();
  const Vec3& g = m.opt.gravity;
  for (size_t c = 0; c < m.road_cars.size(); ++c) {
    const RoadCar& rc = m.road_cars[c];
    const RoadCarParams& p = rc.p;
    const CarRuntime& in = ws.car_inputs[c];
    RoadCarOut& out = ws.road[c];
    const int b = rc.body, A = base + rc.aux;
    const Mat3& R = ws.R[b];
    const Vec3 nb = R.col(2), v = ws.vel[b], om_b = ws.omega[b];
    // I_w om as R (I_b (R^T om)): no R I_b R^T unless the stick-slip solve needs it
    const Mat3& Ib = m.bodies[b].inertia;
    const Vec3 Iw_om = R * (Ib * (R.transpose() * om_b)), gyro = om_b.cross(Iw_om);
    const double r = p.wheel_radius, I = p.wheel_inertia, mu_scene = m.opt.contact.friction;
    // reciprocals: one division each per evaluation, multiplications per wheel
    const double inv_r = 1.0 / r, inv_I = 1.0 / I, inv_h = 1.0 / h, inv_mu = 1.0 / p.wheel_mass;

    // powertrain: one engine for the driven wheels
    const PowertrainParams& pt = p.powertrain;
    const bool fd = pt.drive != Drive::Rear, rd = pt.drive != Drive::Front;
    double wsum = 0.0;
    int nd = 0;
    for (int w = 0; w < 4; ++w)
      if ((w < 2 && fd) || (w >= 2 && rd)) {
        wsum += y[A + roadAux(w, 2)];
        ++nd;
      }
    const DriveOut drive = driveTorque(pt, in.gear, in.applied.throttle, nd ? wsum / nd : 0.0);
    out.engine_rpm = drive.engine_omega * 60.0 / (2.0 * 3.14159265358979323846);
    double axle_torque[2] = {0.0, 0.0};  // open differential: equal halves per axle
    if (pt.drive == Drive::All) {
      axle_torque[0] = pt.front_share * drive.wheel_torque;
      axle_torque[1] = (1.0 - pt.front_share) * drive.wheel_torque;
    } else {
      axle_torque[pt.drive == Drive::Front ? 0 : 1] = drive.wheel_torque;
    }

    double delta[4] = {0.0, 0.0, 0.0, 0.0};
    ackermannAngles(p.steering, p.wheelbase, p.track, in.steer_angle, &delta[0], &delta[1]);

    // the world-frame mass matrix only for the stick-slip tyres' solve; the
    // accelerations come from the body-frame inverse built once
    const bool rigid_tyres = !p.tyre[0].slip_model || !p.tyre[1].slip_model;
    Eigen::Matrix<double, 6, 6> M;
    if (rigid_tyres) {
      M.setZero();
      M.topLeftCorner<3, 3>() = m.bodies[b].mass * Mat3::Identity();
      M.bottomRightCorner<3, 3>() = R * Ib * R.transpose();
    }
    Eigen::Matrix<double, 6, 1> G;
    G.head<3>() = ws.body_force[b] - 0.5 * p.aero.air_density * p.aero.drag_area * v.norm() * v;
    G.tail<3>() = ws.body_torque[b] - gyro;
    double Q[4];
    Vec3 rhub[4];
    double drive_power = 0.0;
    std::array<StickSlipWheel, 4> rigid{};  // stick-slip tyres: solved after the loop
    // three passes over the wheels, so that the transcendental functions of
    // all four run together (vector_math.hpp): the patches, then the tyres'
    // curves, slip angles and rolling resistance, then forces and torques
    struct Patch {
      double s, sd, om, ux, uy, Fz, dux, duy, vx, vy;
      Vec3 r_hub, v_hub, axle, r_c, F;
    };
    std::array<Patch, 4> pw;
    TyreLanes lanes;
    alignas(32) double spin_arg[4], slip_y[4], slip_x[4];
    for (int w = 0; w < 4; ++w) {
      const int ax = w < 2 ? 0 : 1;
      const TyreParams& tp = p.tyre[ax];
      RoadWheelOut& o = out.wheel[w];
      StickSlipWheel& ss = rigid[w];
      Patch& q = pw[w];
      ss.active = !tp.slip_model;
      q.s = y[A + roadAux(w, 0)], q.sd = y[A + roadAux(w, 1)], q.om = y[A + roadAux(w, 2)];
      q.ux = y[A + roadAux(w, 3)], q.uy = y[A + roadAux(w, 4)];
      const Vec3 r_hub = R * rc.hub[w] + q.s * nb;
      q.r_hub = rhub[w] = r_hub;
      const Vec3 p_hub = ws.com[b] + r_hub;
      q.v_hub = v + om_b.cross(r_hub) + q.sd * nb;
      const double cd = delta[w] == 0.0 ? 1.0 : std::cos(delta[w]);  // straight ahead: no trig
      const double sn = delta[w] == 0.0 ? 0.0 : std::sin(delta[w]);
      q.axle = R * Vec3(-sn, cd, 0.0);
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
        const Vec3 head = R * Vec3(cd, sn, 0.0);
        const Vec3 along = head - head.dot(n) * n;
        const double along2 = along.squaredNorm();
        o.tx = along2 > 0.0 ? Vec3(along * (1.0 / std::sqrt(along2))) : along;
        o.ty = n.cross(o.tx);
        const Vec3 vc = v + om_b.cross(q.r_c) + q.sd * nb;
        q.vx = vc.dot(o.tx), q.vy = vc.dot(o.ty);
        q.Fz = std::max(0.0, tp.vertical_stiffness * pen - tp.vertical_damping * q.v_hub.dot(n));
        // the ground's friction at the patch (patches and maps, surface_friction.hpp)
        const double mu_ground = m.ground->friction(ws.com[b] + q.r_c, mu_scene);
        if (ss.active) {
          stickSlipPatch(tp, q.Fz, mu_ground, q.r_c, o, ss);
          q.F = q.Fz * n;
          q.dux = -20.0 * q.ux;  // unused: the tread has no deflection
          q.duy = -20.0 * q.uy;
        } else {
          deflectionRates(tp, q.vx, q.vy, q.om * r, q.ux, q.uy, &q.dux, &q.duy);
          lanes.on[w] = true;
          lanes.t[w] = &tp;
          lanes.Fz[w] = q.Fz;
          lanes.Fz0[w] = rc.nominal_load[w];
          lanes.inv_Fz0[w] = rc.inv_nominal_load[w];
          lanes.mu[w] = mu_ground;
          lanes.kx[w] = q.ux * tp.inv_relaxation;
          lanes.ky[w] = q.uy * tp.inv_relaxation;
          q.F = q.Fz * n;  // the tread's forces are added below
        }
      } else {
        o.hold = 0.0;
        q.dux = -20.0 * q.ux;  // off the ground the tread relaxes
        q.duy = -20.0 * q.uy;
        q.vx = q.vy = 0.0;
      }
      spin_arg[w] = q.om * r / 0.1;
      slip_y[w] = q.vy;
      slip_x[w] = std::max(std::abs(q.vx), 0.5);
    }
    alignas(32) double tyre_fx[4], tyre_fy[4], slip_angle[4], spin_tanh[4];
    tyreForces4(lanes, wide, tyre_fx, tyre_fy);
    atan2_4(slip_y, slip_x, slip_angle, wide);
    tanh4(spin_arg, spin_tanh, wide);
    for (int w = 0; w < 4; ++w) {
      const int ax = w < 2 ? 0 : 1;
      const TyreParams& tp = p.tyre[ax];
      RoadWheelOut& o = out.wheel[w];
      StickSlipWheel& ss = rigid[w];
      const Patch& q = pw[w];
      const double s = q.s, sd = q.sd, om = q.om, ux = q.ux, uy = q.uy, Fz = q.Fz;
      const Vec3 &r_hub = q.r_hub, &axle = q.axle, &r_c = q.r_c;
      double dux = q.dux, duy = q.duy;
      Vec3 F = q.F;
      if (o.contact) {
        if (!ss.active) {
          double Fx = tyre_fx[w], Fy = tyre_fy[w];
          // low-speed damping of the deflection springs (they would ring at standstill)
          const double fade = std::max(0.0, 1.0 - std::abs(q.vx) * (1.0 / 3.0));
          // near standstill a tread deflected past the peak slides instead of
          // stretching further: stop its growth (else a sliding stop winds up
          // a deflection that throws the car back once it halts)
          const double kxn = ux * tp.inv_relaxation * tp.inv_peak_slip_ratio;
          const double kyn = uy * tp.inv_relaxation * tp.inv_peak_slip_angle;
          o.hold = kxn * kxn + kyn * kyn > 1.0 ? fade : 0.0;
          holdGrowth(o.hold, ux, uy, &dux, &duy);
          Fx += tp.low_speed_damping * fade * dux;
          Fy += tp.low_speed_damping * fade * duy;
          const double cap = lanes.mu[w] * tp.friction_scale * Fz, mag = std::sqrt(Fx * Fx + Fy * Fy);
          if (mag > cap && mag > 0.0) {
            const double scale = cap / mag;
            Fx *= scale;
            Fy *= scale;
          }
          F = Fx * o.tx + Fy * o.ty + F;
          o.fx = Fx;
          o.fy = Fy;
        }
        o.slip_ratio = (om * r - q.vx) / std::max(std::abs(q.vx), 0.5);
        o.slip_angle = slip_angle[w];
      } else {
        o.fx = o.fy = o.slip_ratio = o.slip_angle = 0.0;
      }
      o.r = r_c;
      // spin: drive, rolling resistance, the tyre's moment about the axle, then
      // the brake. The moment arm is the rolling radius r, the one the slip
      // ratio uses: with the loaded radius the tyre would return more power
      // to the car than the wheel gives it (by 1 - r_loaded / r, ~5%)
      const double Mgeo = (r_c - r_hub).cross(F).dot(axle);  // what the body does not get
      const double Mha = -(o.contact ? o.fx : 0.0) * r;
      const double t_rr = -tp.rolling_resistance * Fz * r * spin_tanh[w];
      double t_d = axle_torque[ax] * 0.5 + in.applied.wheel_torque[w];
      const double vx_c = o.contact ? (v + om_b.cross(r_c)).dot(o.tx) : 0.0;
      const double kp = tp.peak_slip_ratio;
      if (!ss.active && p.brakes.traction_control && o.contact && t_d > 0.0) {
        const double w_top = (vx_c + std::max(kp * std::abs(vx_c), 0.3)) * inv_r;
        t_d = std::min(t_d, std::max(0.0, I * (w_top - om) * inv_h - (t_rr + Mha)));
      }
      const BrakeParams& bp = p.brakes;
      const bool hand = ax == 1 && in.applied.handbrake;
      const double cap = in.applied.brake * bp.max_torque * 0.5 * (ax == 0 ? bp.front_share : 1.0 - bp.front_share) +
                         (hand ? bp.handbrake_torque : 0.0);
      if (ss.active) stickSlipWheel(p, hand, vx_c, om, sd, r_hub, axle, cap, t_rr, ss, &t_d);
      const double t_other = t_d + t_rr + Mha;
      double t_b = ss.active ? 0.0 : std::clamp(-(I * om * inv_h + t_other), -cap, cap);  // stops the wheel within h at most
      if (!ss.active && bp.abs && !hand && o.contact && std::abs(vx_c) > bp.abs_min_speed) {
        const double lim = I * ((1.0 - kp) * vx_c * inv_r - om) * inv_h - t_other;
        t_b = vx_c > 0.0 ? std::max(t_b, std::min(0.0, lim)) : std::min(t_b, std::max(0.0, lim));
      }
      o.drive_torque = t_d;
      o.brake_torque = t_b;
      o.normal = Fz;
      o.force = F;
      o.travel = s;
      o.steer = delta[w];
      drive_power += t_d * om;

      const double s_other = y[A + roadAux(w ^ 1, 0)];
      Q[w] = F.dot(nb) + p.wheel_mass * g.dot(nb) - springForce(rc, w, s, sd, s_other);
      G.head<3>() += F - Q[w] * nb;
      G.tail<3>() += r_c.cross(F) - (Mgeo + t_d + t_b) * axle - Q[w] * r_hub.cross(nb);
      if (rigid_tyres) {
        Eigen::Matrix<double, 6, 1> j;
        j << nb, r_hub.cross(nb);
        M.noalias() -= p.wheel_mass * j * j.transpose();
      }
      double* d = ws.aux_dot.data() + rc.aux + 5 * w;
      d[0] = sd;
      d[2] = (t_d + t_b + t_rr + Mha) * inv_I;
      d[3] = dux;
      d[4] = duy;
    }
    // the stick-slip tyres' friction and brakes need the body's mass matrix
    if (rigid_tyres) {
      const StickSlipBody sb{&M, &G, v, om_b, ws.inv_inertia_world[b] * gyro, nb, Q};
      applyStickSlipTyres(p, sb, h, rigid, out, ws.aux_dot.data() + rc.aux);
    }
    // M = T M_b T^T with T = diag(R, R) and M_b constant (road_car.hpp)
    Eigen::Matrix<double, 6, 1> Gb;
    Gb.head<3>().noalias() = R.transpose() * G.head<3>();
    Gb.tail<3>().noalias() = R.transpose() * G.tail<3>();
    const Eigen::Matrix<double, 6, 1> acc_b = rc.inv_mass_body * Gb;
    const Vec3 a_lin = R * acc_b.head<3>(), alpha = R * acc_b.tail<3>();
    ws.body_force[b] = m.bodies[b].mass * a_lin;
    ws.body_torque[b] = R * (Ib * acc_b.tail<3>()) + gyro;  // I_w alpha + om x I_w om
    for (int w = 0; w < 4; ++w)
      ws.aux_dot[rc.aux + 5 * w + 1] = Q[w] * inv_mu - (nb.dot(a_lin) + rhub[w].cross(nb).dot(alpha));
    out.drive_power = drive_power;
    ws.drive_power += drive_power;
  }
}

GROUNDSIM_WIDE void roadCarsWide(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  roadCarsBody(m, y, h, ws, true);
}
void roadCarsGeneric(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  roadCarsBody(m, y, h, ws, false);
}

}  // namespace

void applyRoadCars(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  if (useWideSimd(m)) roadCarsWide(m, y, h, ws);
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
