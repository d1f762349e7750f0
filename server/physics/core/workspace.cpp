#include "physics/core/workspace.hpp"

#include <algorithm>

namespace groundsim {

Workspace::Workspace(const Model& m, bool with_diagnostics) : ground(*m.ground) {
  const size_t nb = m.bodies.size(), np = m.points.size(), nq = m.particles.size(),
               nw = m.wheels.size();
  R.assign(nb, Mat3::Identity());
  inv_inertia_world.assign(nb, Mat3::Zero());
  com.assign(nb, Vec3::Zero());
  vel.assign(nb, Vec3::Zero());
  omega.assign(nb, Vec3::Zero());
  for (auto* v : {&lx, &ly, &lz, &px, &py, &pz, &ux, &uy, &uz, &fx, &fy, &fz, &H}) v->assign(np, 0.0);
  for (size_t k = 0; k < np; ++k) {
    lx[k] = m.points[k].local.x();
    ly[k] = m.points[k].local.y();
    lz[k] = m.points[k].local.z();
  }
  body_far.assign(nb, 0);
  contacts.assign(m.contact_points.size() + nw, Contact{});
  body_force.assign(nb, Vec3::Zero());
  body_torque.assign(nb, Vec3::Zero());
  particle_force.assign(nq, Vec3::Zero());
  v_pred.assign(nb, Vec3::Zero());
  w_pred.assign(nb, Vec3::Zero());
  pv_pred.assign(nq, Vec3::Zero());
  brake_impulse.assign(nw, 0.0);
  wheel_normal.assign(nw, 0.0);
  wheel_friction.assign(nw, 0.0);
  wheel_slip.assign(nw, 0.0);
  group_lo.assign(m.groups.size(), Vec3::Zero());
  group_hi.assign(m.groups.size(), Vec3::Zero());
  group_com.assign(m.groups.size(), Vec3::Zero());
  group_box.assign(m.groups.size(), OrientedBox{});
  group_pad.assign(m.groups.size(), 0.0);
  sweep.resize(m.groups.size());
  for (size_t g = 0; g < m.groups.size(); ++g) sweep[g] = static_cast<int>(g);
  pairs.reserve(4 * m.groups.size());
  pair_contacts.reserve(4 * m.groups.size());
  census_range.reserve(4 * m.groups.size());
  census.reserve(m.probes.size());
  phase_cars.reserve(m.road_cars.size());
  in_phase.assign(m.bodies.size(), 0);
  phase_force.reserve(m.road_cars.size());
  phase_torque.reserve(m.road_cars.size());
  phase_travel.reserve(m.road_cars.size());
  car_inputs.assign(m.road_cars.size(), CarRuntime{});
  applied_mark.assign(m.wheels.size(), WheelControl{});
  cars_mark.assign(m.road_cars.size(), CarRuntime{});
  road.assign(m.road_cars.size(), RoadCarOut{});
  aux_dot.setZero(m.aux_states);
  const int n = m.stateSize();
  for (Eigen::VectorXd* v : {&dy, &ytmp, &k1, &k2, &k3, &k4, &k5, &k6, &k7, &err}) v->setZero(n);
  if (with_diagnostics && m.opt.integrator == IntegratorKind::ImplicitEuler) {
    fd_scale.setOnes(n);
    for (size_t i = 0; i < nb; ++i)
      fd_scale.segment<3>(13 * i + 10).setConstant(std::max(m.bodies[i].inertia.diagonal().maxCoeff(), 1e-12));
    jac.setZero(n, n);
    lhs.setZero(n, n);
    lu = Eigen::PartialPivLU<Eigen::MatrixXd>(n);
  }
  if (with_diagnostics && m.opt.integrator == IntegratorKind::VelocityVerlet) {
    verlet.y.setZero(n);
    verlet.controls.assign(nw, WheelControl{});
    verlet.force.assign(nb, Vec3::Zero());
    verlet.torque.assign(nb, Vec3::Zero());
    verlet.particle_force.assign(nq, Vec3::Zero());
  }
  last_good.y.setZero(n);
  last_good.controls.assign(nw, WheelControl{});
  last_good.applied.assign(nw, WheelControl{});
  last_good.health_reason.reserve(256);
  if (with_diagnostics) diagnostics = std::make_unique<Workspace>(m, false);
}

}  // namespace groundsim
