// Report eqs. (7), (9), (16), (17): gravity plus every point force, summed
// into each body's force and its torque about the centre of mass.
#include <cmath>

#include "physics/forces/forces.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim {

namespace {

GROUNDSIM_INLINE_BODY void accumulateBody(const Model& m, Workspace& ws) {
  const Vec3& g = m.opt.gravity;
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    ws.body_force[i] = m.bodies[i].mass * g;
    ws.body_torque[i].setZero();
  }
  for (size_t j = 0; j < m.particles.size(); ++j)
    ws.particle_force[j] = m.particles[j].mass * g + ws.springForce(m.particle_points[j]);
  // sum f and (p - c) x f over each body's points (a vectorisable reduction)
  for (size_t i = 0; i < m.bodies.size(); ++i) {
    const double cx = ws.com[i].x(), cy = ws.com[i].y(), cz = ws.com[i].z();
    double Fx = 0, Fy = 0, Fz = 0, Tx = 0, Ty = 0, Tz = 0;
    const double *px = ws.px.data(), *py = ws.py.data(), *pz = ws.pz.data();
    const double *fxs = ws.fx.data(), *fys = ws.fy.data(), *fzs = ws.fz.data();
    const int kb = m.body_point_begin[i], ke = m.body_point_end[i];
#pragma omp simd reduction(+ : Fx, Fy, Fz, Tx, Ty, Tz)
    for (int k = kb; k < ke; ++k) {
      const double rx = px[k] - cx, ry = py[k] - cy, rz = pz[k] - cz;
      const double fx = fxs[k], fy = fys[k], fz = fzs[k];
      Fx += fx;
      Fy += fy;
      Fz += fz;
      Tx += ry * fz - rz * fy;
      Ty += rz * fx - rx * fz;
      Tz += rx * fy - ry * fx;
    }
    ws.body_force[i] += Vec3(Fx, Fy, Fz);
    ws.body_torque[i] += Vec3(Tx, Ty, Tz);
  }
  for (int i = 0; i < ws.ncontacts; ++i) {
    const Contact& c = ws.contacts[i];
    const Vec3 f = c.normal * c.n + c.friction;
    if (c.body >= 0) {
      ws.body_force[c.body] += f;
      ws.body_torque[c.body] += c.r.cross(f);
    } else {
      ws.particle_force[c.particle] += f;
    }
  }
}

GROUNDSIM_WIDE void accumulateWide(const Model& m, Workspace& ws) { accumulateBody(m, ws); }
void accumulateGeneric(const Model& m, Workspace& ws) { accumulateBody(m, ws); }

}  // namespace

void accumulateBodyForces(const Model& m, Workspace& ws) {
  if (useWideSimd(m.opt.deterministic)) accumulateWide(m, ws);
  else accumulateGeneric(m, ws);
}

// Drive torque about the wheel's own axle, and the equal and opposite
// reaction on its carrier (the report adds momentum to the wheels only, which
// creates angular momentum from nothing).
void applyDrive(const Model& m, const std::vector<WheelControl>& controls, Workspace& ws) {
  ws.drive_power = 0.0;
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const double T = controls[w].drive_torque;
    if (T == 0.0) continue;
    const Wheel& wh = m.wheels[w];
    const Vec3 a = ws.R[wh.body] * wh.axis;
    ws.body_torque[wh.body] += T * a;
    if (wh.carrier < 0) {  // a lone wheel: an external torque
      ws.drive_power += T * a.dot(ws.omega[wh.body]);
      continue;
    }
    ws.body_torque[wh.carrier] -= T * a;
    ws.drive_power += T * a.dot(ws.omega[wh.body] - ws.omega[wh.carrier]);
  }
}

void applyRegularizedBrakes(const Model& m, const std::vector<WheelControl>& controls, Workspace& ws) {
  const double vs = m.opt.contact.slip_velocity;
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    const double B = controls[w].brake_torque;
    const Wheel& wh = m.wheels[w];
    if (!(B > 0.0) || wh.carrier < 0) continue;
    const Vec3 a = ws.R[wh.body] * wh.axis;
    const double spin = a.dot(ws.omega[wh.body] - ws.omega[wh.carrier]);
    const Vec3 tq = (-B * std::tanh(spin * wh.radius / vs)) * a;
    ws.body_torque[wh.body] += tq;
    ws.body_torque[wh.carrier] -= tq;
  }
}

}  // namespace groundsim
