// Contact between bodies as its own phase of a semi-implicit Euler step
// (multi-rate, as the impulse method of r-RESPA splits fast forces from
// slow ones). A pair in contact needs substeps of the step (its penalty
// springs are stiff, docs/contact.md); the cars' tyres, suspension and
// powertrain do not, and evaluating them in every substep was most of what
// a pushing pair cost. Here the slow forces are evaluated once at the
// step's start and held, and only the contact and the motion of the cars
// it joins are substepped.
#include "physics/integrators/contact_phase.hpp"

#include <algorithm>

#include "physics/forces/body_contact.hpp"
#include "physics/forces/forces.hpp"
#include "physics/forces/road_car_phase.hpp"
#include "physics/integrators/integrator_methods.hpp"

namespace groundsim {

namespace {

int roadCarOfBody(const Model& m, int body) {
  for (size_t c = 0; c < m.road_cars.size(); ++c)
    if (m.road_cars[c].body == body) return static_cast<int>(c);
  return -1;
}

// A group the phase can hold: static, or a road car on slip tyres (whose
// response to a force on its body is linear: reducedMassBody).
bool phaseGroup(const Model& m, const CollisionGroup& g) {
  if (g.ref_body < 0) return true;
  const int c = roadCarOfBody(m, g.ref_body);
  return c >= 0 && g.rigid && m.road_cars[c].p.tyre[0].slip_model && m.road_cars[c].p.tyre[1].slip_model;
}

// The road cars of the step's pairs, each once.
void collectCars(const Model& m, Workspace& ws) {
  ws.phase_cars.clear();
  std::fill(ws.in_phase.begin(), ws.in_phase.end(), 0);
  for (const auto& [a, b] : ws.pairs)
    for (int g : {a, b}) {
      const int body = m.groups[g].ref_body;
      if (body < 0 || ws.in_phase[body]) continue;
      ws.in_phase[body] = 1;
      ws.phase_cars.push_back(roadCarOfBody(m, body));
    }
}

// Semi-implicit Euler over dt for what the phase does not substep: the
// bodies of no pair, the particles, the road cars' spin (and the travel
// rate of the cars of no pair).
void stepTheRest(const Model& m, State& s, const Workspace& ws, double dt) {
  semiImplicitBodiesAndParticles(m, s.y, ws, dt, ws.in_phase.data());
  const int base = m.auxBase();
  for (const RoadCar& rc : m.road_cars)
    for (int w = 0; w < 4; ++w) {
      const int i = rc.aux + 5 * w;
      if (!ws.in_phase[rc.body]) s.y[base + i + 1] += dt * ws.aux_dot[i + 1];
      s.y[base + i + 2] += dt * ws.aux_dot[i + 2];
    }
}

// What the phase holds of each of its cars: the slow evaluation's force,
// torque and travel accelerations.
void holdSlowForces(const Model& m, Workspace& ws) {
  const size_t n = ws.phase_cars.size();
  ws.phase_force.resize(n);
  ws.phase_torque.resize(n);
  ws.phase_travel.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const RoadCar& rc = m.road_cars[ws.phase_cars[j]];
    ws.phase_force[j] = ws.body_force[rc.body];
    ws.phase_torque[j] = ws.body_torque[rc.body];
    for (int w = 0; w < 4; ++w) ws.phase_travel[j][w] = ws.aux_dot[rc.aux + 5 * w + 1];
  }
}

// The cars' frames and velocities at configuration y (what the narrow
// phase reads), their contact forces zeroed.
void carKinematics(const Model& m, const Eigen::VectorXd& y, Workspace& ws) {
  for (int c : ws.phase_cars) {
    const int b = m.road_cars[c].body;
    bodyFrame(m, y, b, ws);
    ws.body_force[b].setZero();
    ws.body_torque[b].setZero();
  }
}

// One substep h of each car: its contact force and torque (in
// body_force, body_torque) through its reduced mass, added to the held
// forces; momenta, then position and the midpoint rotation, then the
// struts' travel rates.
void moveCars(const Model& m, State& s, Workspace& ws, double h) {
  const int base = m.auxBase();
  for (size_t j = 0; j < ws.phase_cars.size(); ++j) {
    const RoadCar& rc = m.road_cars[ws.phase_cars[j]];
    const int b = rc.body;
    const Mat3& R = ws.R[b];
    // the body's accelerations under the contact, as bodyAccelerations
    // (road_cars.cpp) gives them for any force on the body
    Eigen::Matrix<double, 6, 1> Gb;
    Gb.head<3>().noalias() = R.transpose() * ws.body_force[b];
    Gb.tail<3>().noalias() = R.transpose() * ws.body_torque[b];
    const Eigen::Matrix<double, 6, 1> acc_b = rc.inv_mass_body * Gb;
    const Vec3 a_lin = R * acc_b.head<3>();
    const Vec3 torque = R * (m.bodies[b].inertia * acc_b.tail<3>());
    semiImplicitBodyUpdate(m, s.y, b, h * (ws.phase_force[j] / m.bodies[b].mass + a_lin),
                           h * (ws.phase_torque[j] + torque), ws.inv_inertia_world[b], h);
    // a strut's travel: the body's acceleration along it at the hub (the
    // struts are the body's z axis: body-frame constants)
    for (int w = 0; w < 4; ++w) {
      const Vec3 arm = rc.hub[w].cross(Vec3::UnitZ());
      const double along = acc_b[2] + arm.dot(acc_b.tail<3>());
      s.y[base + rc.aux + 5 * w + 1] += h * (ws.phase_travel[j][w] - along);
    }
    ws.body_force[b] = ws.phase_force[j] + m.bodies[b].mass * a_lin;  // the total, for telemetry
    ws.body_torque[b] = ws.phase_torque[j] + torque;
  }
}

}  // namespace

bool contactPhaseApplies(const Model& m, const Workspace& ws) {
  if (m.opt.integrator != IntegratorKind::SemiImplicitEuler) return false;
  if (std::max(m.opt.substeps, m.object_substeps) > 1 || !ws.step_census || ws.pairs.empty()) return false;
  for (size_t k = 0; k < ws.pairs.size(); ++k) {
    if (ws.census_range[k][0] < 0) return false;
    if (!phaseGroup(m, m.groups[ws.pairs[k].first]) || !phaseGroup(m, m.groups[ws.pairs[k].second])) return false;
  }
  return true;
}

void contactPhaseStep(const Model& m, State& s, Workspace& ws, double dt, int n) {
  // every force but contact between bodies, once, at the step's start
  ws.defer_body_contacts = true;
  computeForces(m, s.y, s.applied, dt, ws);
  ws.defer_body_contacts = false;
  s.drive_work += dt * ws.drive_power;
  collectCars(m, ws);
  stepTheRest(m, s, ws, dt);
  holdSlowForces(m, ws);
  // the cars of the pairs: n substeps of their contact
  const double h = dt / n;
  double depth = ws.max_depth;
  for (int k = 0; k < n; ++k) {
    carKinematics(m, s.y, ws);
    bodyContacts(m, true, ws);
    depth = std::max(depth, ws.body_contact_depth);
    moveCars(m, s, ws, h);
  }
  ws.max_depth = depth;
  driftRoadCars(m, s.y, ws, dt);
}

}  // namespace groundsim
