// Stick-slip friction and brakes at the velocity level. Each contact may
// apply a tangential impulse of at most mu N h, chosen to cancel the slip the
// step is about to produce; each brake an impulse of at most B h about its
// axle. Projected Gauss-Seidel over all of them: a parked car on a slope
// holds exactly (no creep) and the slip never reverses (no chatter), which
// the report's sign() friction cannot do.
//
// This is a time-stepper's solve: the impulses depend on the step h they
// are sized for, so only semi-implicit Euler and velocity Verlet (which own
// the velocity update it predicts) may use it; checkIntegratorFriction
// refuses it with the ODE integrators. With regularized friction the brakes
// are smooth too (applyRegularizedBrakes) and nothing here runs.
#include <algorithm>
#include <cmath>

#include "physics/base/pointwise.hpp"
#include "physics/forces/forces.hpp"

namespace groundsim {
namespace {

bool needsPass(const Model& m, const std::vector<WheelControl>& controls, const Workspace& ws) {
  if (m.opt.contact.friction_model == FrictionModel::StickSlip && ws.ncontacts > 0) return true;
  if (!velocityLevelBrakes(m)) return false;  // applyRegularizedBrakes has them
  for (const auto& c : controls)
    if (c.brake_torque > 0.0) return true;
  return false;
}

// Tangent basis and the 2x2 effective mass a tangential impulse sees:
// K_ij = t_i . t_j / m + (r x t_i) . I^-1 (r x t_j).
void prepareFriction(const Model& m, const Workspace& ws, Contact& c) {
  c.t1 = c.n.unitOrthogonal();
  c.t2 = c.n.cross(c.t1);
  Eigen::Matrix2d K;
  if (c.body >= 0) {
    const double inv_m = 1.0 / m.bodies[c.body].mass;
    c.a1 = c.r.cross(c.t1);
    c.a2 = c.r.cross(c.t2);
    c.b1 = ws.inv_inertia_world[c.body] * c.a1;
    c.b2 = ws.inv_inertia_world[c.body] * c.a2;
    const double k12 = c.a1.dot(c.b2);
    K << inv_m + c.a1.dot(c.b1), k12, k12, inv_m + c.a2.dot(c.b2);
  } else {
    K = Eigen::Matrix2d::Identity() / m.particles[c.particle].mass;
  }
  c.k = K;
  c.k_inv = K.inverse();
  c.impulse.setZero();
}

// Velocities at the end of the step if friction and brakes did nothing.
void predictVelocities(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws) {
  const int nb = static_cast<int>(m.bodies.size());
  for (int i = 0; i < nb; ++i) {
    ws.v_pred[i] = ws.vel[i] + h * ws.body_force[i] / m.bodies[i].mass;
    ws.w_pred[i] = ws.inv_inertia_world[i] * (bodyMom(y, i) + h * ws.body_torque[i]);
  }
  for (size_t j = 0; j < m.particles.size(); ++j)
    ws.pv_pred[j] = y.segment<3>(particleOffset(nb, static_cast<int>(j)) + 3) +
                    h * ws.particle_force[j] / m.particles[j].mass;
}

// The largest impulse any of them may apply: the floor of the convergence
// test, for free rolling needs (almost) no friction at all.
double impulseScale(const std::vector<WheelControl>& controls, double h, bool stick, const Workspace& ws) {
  double scale = 0.0;
  if (stick)
    for (int i = 0; i < ws.ncontacts; ++i) scale += ws.contacts[i].mu * ws.contacts[i].normal * h;
  for (const auto& c : controls) scale += std::max(c.brake_torque, 0.0) * h;
  return scale;
}

// One sweep's brakes: each braked wheel's impulse about its axle, clamped
// to B h, against its carrier. Adds to change and total.
void brakeSweep(const Model& m, const std::vector<WheelControl>& controls, double h, Workspace& ws, double& change,
                double& total) {
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const double B = controls[w].brake_torque;
    const Wheel& wh = m.wheels[w];
    if (!(B > 0.0) || wh.carrier < 0) continue;
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
}

// One sweep's contacts: each contact's tangential impulse, inside its
// friction disc. Adds to change and total.
void contactSweep(const Model& m, double h, Workspace& ws, double& change, double& total) {
  for (int i = 0; i < ws.ncontacts; ++i) {
    Contact& c = ws.contacts[i];
    // tangential velocity t . (v + w x r) = t . v + w . (r x t)
    Eigen::Vector2d ut;
    if (c.body >= 0) {
      const Vec3& v = ws.v_pred[c.body];
      const Vec3& w = ws.w_pred[c.body];
      ut = Eigen::Vector2d(c.t1.dot(v) + w.dot(c.a1), c.t2.dot(v) + w.dot(c.a2));
    } else {
      ut = Eigen::Vector2d(c.t1.dot(ws.pv_pred[c.particle]), c.t2.dot(ws.pv_pred[c.particle]));
    }
    Eigen::Vector2d acc = c.impulse - c.k_inv * ut;
    const double limit = c.mu * c.normal * h;
    const double an = acc.norm();
    if (an > limit) {
      // sliding: mu N opposite the slip this contact would have without
      // its own friction. Scaling the stick impulse onto the disc instead
      // tilts the force off the slip wherever rotation couples the two
      // tangent directions (a skidding box then stops 2% late); using the
      // slip after friction makes the sweeps converge slowly.
      const Eigen::Vector2d free = ut - c.k * c.impulse;
      const double fn = free.norm();
      acc = fn > 1e-12 ? Eigen::Vector2d(-limit / fn * free) : Eigen::Vector2d(acc * (limit / an));
    }
    const Eigen::Vector2d d = acc - c.impulse;
    c.impulse = acc;
    change += d.lpNorm<1>();
    total += acc.lpNorm<1>();
    const Vec3 J = d.x() * c.t1 + d.y() * c.t2;
    if (c.body >= 0) {
      ws.v_pred[c.body] += J / m.bodies[c.body].mass;
      ws.w_pred[c.body] += d.x() * c.b1 + d.y() * c.b2;
    } else {
      ws.pv_pred[c.particle] += J / m.particles[c.particle].mass;
    }
  }
}

// Sweep until the impulses stop changing: a fixed small count leaves a
// residual slip every step, which integrates into creep.
void sweeps(const Model& m, const std::vector<WheelControl>& controls, double h, bool stick, double scale,
            Workspace& ws) {
  for (int iter = 0; iter < m.opt.contact.friction_iterations; ++iter) {
    double change = 0.0, total = 0.0;
    brakeSweep(m, controls, h, ws, change, total);
    if (stick) contactSweep(m, h, ws, change, total);
    ws.friction_sweeps = iter + 1;
    if (pointwise::converged(change, total, scale)) break;
  }
}

// Impulses over the step become forces for the integrator and telemetry:
// the brakes' torques on wheel and carrier, then (stick) the contacts'.
void impulsesAsForces(const Model& m, double h, bool stick, Workspace& ws) {
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const Wheel& wh = m.wheels[w];
    if (ws.brake_impulse[w] == 0.0 || wh.carrier < 0) continue;
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

}  // namespace

void solveVelocityConstraints(const Model& m, const Eigen::VectorXd& y,
                              const std::vector<WheelControl>& controls, double h, Workspace& ws) {
  if (!needsPass(m, controls, ws)) return;
  predictVelocities(m, y, h, ws);
  const bool stick = m.opt.contact.friction_model == FrictionModel::StickSlip;
  if (stick) {
    for (int i = 0; i < ws.ncontacts; ++i) prepareFriction(m, ws, ws.contacts[i]);
  }
  for (auto& b : ws.brake_impulse) b = 0.0;
  const double scale = impulseScale(controls, h, stick, ws);
  sweeps(m, controls, h, stick, scale, ws);
  impulsesAsForces(m, h, stick, ws);
}

}  // namespace groundsim
