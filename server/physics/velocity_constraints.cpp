// Stick-slip friction and brakes at the velocity level. Each contact may
// apply a tangential impulse of at most mu N h, chosen to cancel the slip the
// step is about to produce; each brake an impulse of at most B h about its
// axle. Projected Gauss-Seidel over all of them: a parked car on a slope
// holds exactly (no creep) and the slip never reverses (no chatter), which
// the report's sign() friction cannot do.
#include <cmath>

#include "forces.hpp"

namespace groundsim {
namespace {

bool needsPass(const Model& m, const std::vector<WheelControl>& controls, const Workspace& ws) {
  if (m.opt.contact.friction_model == FrictionModel::StickSlip && ws.ncontacts > 0) return true;
  for (const auto& c : controls)
    if (c.brake_torque > 0.0) return true;
  return false;
}

// Inverse of the 2x2 effective mass a tangential impulse sees at the contact.
Eigen::Matrix2d inverseTangentMass(const Model& m, const Workspace& ws, const Contact& c) {
  Mat3 K;
  if (c.body >= 0) {
    const Mat3 rx = skew(c.r);
    K = Mat3::Identity() / m.bodies[c.body].mass - rx * ws.inv_inertia_world[c.body] * rx;
  } else {
    K = Mat3::Identity() / m.particles[c.particle].mass;
  }
  Eigen::Matrix<double, 3, 2> P;
  P.col(0) = c.t1;
  P.col(1) = c.t2;
  return (P.transpose() * K * P).inverse();
}

}  // namespace

void solveVelocityConstraints(const Model& m, const Eigen::VectorXd& y,
                              const std::vector<WheelControl>& controls, double h, Workspace& ws) {
  if (!needsPass(m, controls, ws)) return;
  const int nb = static_cast<int>(m.bodies.size());
  // velocities at the end of the step if friction and brakes did nothing
  for (int i = 0; i < nb; ++i) {
    ws.v_pred[i] = ws.vel[i] + h * ws.body_force[i] / m.bodies[i].mass;
    ws.w_pred[i] = ws.inv_inertia_world[i] * (bodyMom(y, i) + h * ws.body_torque[i]);
  }
  for (size_t j = 0; j < m.particles.size(); ++j)
    ws.pv_pred[j] = y.segment<3>(particleOffset(nb, static_cast<int>(j)) + 3) +
                    h * ws.particle_force[j] / m.particles[j].mass;

  const bool stick = m.opt.contact.friction_model == FrictionModel::StickSlip;
  const double mu = m.opt.contact.friction;
  if (stick) {
    for (int i = 0; i < ws.ncontacts; ++i) {
      Contact& c = ws.contacts[i];
      c.t1 = c.n.unitOrthogonal();
      c.t2 = c.n.cross(c.t1);
      c.k_inv = inverseTangentMass(m, ws, c);
      c.impulse.setZero();
    }
  }
  for (auto& b : ws.brake_impulse) b = 0.0;

  // sweep until the impulses stop changing: a fixed small count leaves a
  // residual slip every step, which integrates into creep
  for (int iter = 0; iter < m.opt.contact.friction_iterations; ++iter) {
    double change = 0.0, total = 0.0;
    for (size_t w = 0; w < m.wheels.size(); ++w) {
      const double B = controls[w].brake_torque;
      if (!(B > 0.0)) continue;
      const Wheel& wh = m.wheels[w];
      const Vec3 a = ws.R[wh.body] * wh.axis;
      const Vec3 ia = ws.inv_inertia_world[wh.body] * a, ic = ws.inv_inertia_world[wh.carrier] * a;
      const double spin = a.dot(ws.w_pred[wh.body] - ws.w_pred[wh.carrier]);
      const double acc = std::clamp(ws.brake_impulse[w] - spin / (a.dot(ia) + a.dot(ic)), -B * h, B * h);
      const double d = acc - ws.brake_impulse[w];
      ws.brake_impulse[w] = acc;
      change += std::abs(d);
      total += std::abs(acc);
      ws.w_pred[wh.body] += d * ia;
      ws.w_pred[wh.carrier] -= d * ic;
    }
    if (stick) {
    for (int i = 0; i < ws.ncontacts; ++i) {
      Contact& c = ws.contacts[i];
      const Vec3 u = c.body >= 0 ? Vec3(ws.v_pred[c.body] + ws.w_pred[c.body].cross(c.r))
                                 : Vec3(ws.pv_pred[c.particle]);
      const Eigen::Vector2d ut(c.t1.dot(u), c.t2.dot(u));
      Eigen::Vector2d acc = c.impulse - c.k_inv * ut;
      const double limit = mu * c.normal * h;
      const double an = acc.norm();
      if (an > limit) {
        // sliding: mu N opposite the slip (maximum dissipation). Scaling the
        // stick impulse onto the disc instead would tilt the force off the
        // slip wherever rotation couples the two tangent directions.
        const double un = ut.norm();
        acc = un > 1e-12 ? Eigen::Vector2d(-limit / un * ut) : Eigen::Vector2d(acc * (limit / an));
      }
      const Eigen::Vector2d d = acc - c.impulse;
      c.impulse = acc;
      change += d.lpNorm<1>();
      total += acc.lpNorm<1>();
      const Vec3 J = d.x() * c.t1 + d.y() * c.t2;
      if (c.body >= 0) {
        ws.v_pred[c.body] += J / m.bodies[c.body].mass;
        ws.w_pred[c.body] += ws.inv_inertia_world[c.body] * c.r.cross(J);
      } else {
        ws.pv_pred[c.particle] += J / m.particles[c.particle].mass;
      }
    }
    }
    if (change <= 1e-9 * total) break;  // converged (tighter stalls on round-off)
  }

  // impulses over the step become forces for the integrator and telemetry
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    if (ws.brake_impulse[w] == 0.0) continue;
    const Wheel& wh = m.wheels[w];
    const Vec3 tq = (ws.brake_impulse[w] / h) * (ws.R[wh.body] * wh.axis);
    ws.body_torque[wh.body] += tq;
    ws.body_torque[wh.carrier] -= tq;
  }
  if (!stick) return;
  for (int i = 0; i < ws.ncontacts; ++i) {
    Contact& c = ws.contacts[i];
    c.friction = (c.impulse.x() * c.t1 + c.impulse.y() * c.t2) / h;
    if (c.body >= 0) {
      ws.body_force[c.body] += c.friction;
      ws.body_torque[c.body] += c.r.cross(c.friction);
    } else {
      ws.particle_force[c.particle] += c.friction;
    }
    if (c.wheel >= 0) ws.wheel_friction[c.wheel] += c.friction.norm();
  }
}

}  // namespace groundsim
