// The physics core in the page, compiled to WebAssembly: the own car is
// simulated ahead of the server's states with the player's controls, so a
// key moves it on the next frame instead of a round trip later
// (web/src/predict.js drives it; docs/game.md, Prediction).
//
// The server publishes of each car only what state_t carries (the chassis'
// position, orientation, velocities, wheel spins), not the whole core state
// (wheel bodies, a road car's tyre, strut and powertrain states). So a
// server state is applied SuperTuxKart-style with one difference: the local
// state saved before the step at the server's time t is taken, its car is
// moved rigidly (every body of the vehicle) so that its chassis has the
// server's pose and velocities, the states state_t does not carry stay the
// local ones, and the steps from t to the present are run again with the
// controls recorded for them.
//
// One predictor per page (a page drives one car): plain C functions on a
// global, called through Emscripten's ccall/cwrap.
#include <emscripten/emscripten.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "physics/build/vehicle.hpp"
#include "physics/checks/telemetry.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

using namespace groundsim;

namespace {

// States saved before each step, enough for kRingSeconds of lead (a round
// trip of up to 1 s; the page leads by at most 0.5 s) within kRingBytes: the
// sedan (4 ms) keeps 250 states, the report's car (50 us, about 5 kB a
// state) 6,000, 0.3 s.
// A server state older than the oldest saved one cannot be replayed and is
// applied at the present instead.
constexpr double kRingSeconds = 1.0;
constexpr double kRingBytes = 32e6;

struct Predictor {
  scenario::Scene scene;
  std::unique_ptr<Simulator> sim;
  int vehicle = 0;
  int road_car = -1;
  std::vector<int> wheels;       // the vehicle's wheels in drive_t order (front-left, front-right, rear-left, rear-right)
  std::vector<int> bodies;       // the vehicle's bodies: its chassis first
  std::vector<std::vector<int>> vbodies;  // every vehicle's, the same way
  // web/bridge/controls.hpp's ControlScale (the bridge's defaults; set by gs_scale)
  double drive_torque = 1.2, brake_torque = 6.0, steer = kFullLockRad;
  std::vector<State> ring;
  long long kRing = 0;
  long long steps = 0;           // steps taken since create: ring[k % kRing] is the state before step k
  long long oldest = 0;          // the oldest step whose state the ring still holds
};

std::unique_ptr<Predictor> g;
std::string g_error;
double g_pose[13];
double g_last_error = 0.0;  // m: the local chassis at t against the server's, before the last correction

Vec3 chassisOmega(const Model& m, const State& s, int b) {
  const Quat q = bodyRot(s.y, b);
  const Mat3 R = q.toRotationMatrix();
  return R * m.bodies[b].inv_inertia * R.transpose() * Vec3(bodyMom(s.y, b));
}

// Moves the vehicle's bodies rigidly so that its chassis has pose (p, q) and
// velocities (v, w); each body keeps its motion relative to the chassis.
void placeVehicle(const Model& m, State& s, const std::vector<int>& bodies, const Vec3& p, const Quat& q,
                  const Vec3& v, const Vec3& w) {
  const int c = bodies.front();
  const Vec3 P = bodyPos(s.y, c), V = bodyVel(s.y, c), W = chassisOmega(m, s, c);
  const Quat dq = (q * Quat(bodyRot(s.y, c)).conjugate()).normalized();
  const Mat3 R = dq.toRotationMatrix();
  for (int b : bodies) {
    const Vec3 r = Vec3(bodyPos(s.y, b)) - P;
    const Vec3 v_rel = Vec3(bodyVel(s.y, b)) - (V + W.cross(r));
    const Vec3 w_rel = chassisOmega(m, s, b) - W;
    const Vec3 r2 = R * r;
    const Quat qb = (dq * Quat(bodyRot(s.y, b))).normalized();
    const Vec3 wb = w + R * w_rel;
    const Mat3 Rb = qb.toRotationMatrix();
    bodyPos(s.y, b) = p + r2;
    bodyRot(s.y, b) = qb;
    bodyVel(s.y, b) = v + w.cross(r2) + R * v_rel;
    bodyMom(s.y, b) = Rb * m.bodies[b].inertia * Rb.transpose() * wb;
  }
}

void save(Predictor& pr) {
  pr.ring[static_cast<size_t>(pr.steps % pr.kRing)] = pr.sim->state();
  pr.oldest = std::max(pr.oldest, pr.steps - pr.kRing + 1);
}

}  // namespace

extern "C" {

// Builds the scenario (its JSON text) and predicts `vehicle`. 0 on success,
// else -1 and gs_error() says why (a ground the page's build has no reader
// for: heightfield PNGs, expressions).
EMSCRIPTEN_KEEPALIVE int gs_create(const char* scenario_json, int vehicle) {
  g.reset();
  try {
    auto pr = std::make_unique<Predictor>();
    const scenario::Scenario s = scenario::parseScenario(std::string(scenario_json));
    pr->scene = scenario::buildScene(s);
    const Model& m = *pr->scene.built.model;
    if (vehicle < 0 || vehicle >= static_cast<int>(m.vehicle_names.size()))
      throw std::runtime_error("no vehicle " + std::to_string(vehicle));
    pr->vehicle = vehicle;
    pr->sim = std::make_unique<Simulator>(pr->scene.built.model, pr->scene.built.initial);
    pr->road_car = pr->sim->roadCarIndex(vehicle);
    const double state_bytes = 8.0 * m.stateSize() + 64.0 * (m.wheels.size() + m.road_cars.size()) + 256.0;
    pr->kRing = static_cast<long long>(std::clamp(std::min(std::ceil(kRingSeconds / m.opt.dt), kRingBytes / state_bytes), 16.0, 1e6));
    pr->ring.resize(static_cast<size_t>(pr->kRing));
    for (size_t k = 0; k < m.vehicle_names.size(); ++k) {
      std::vector<int> bodies{m.vehicle_body[k]};
      for (size_t w = 0; w < m.wheels.size(); ++w) {
        if (m.vehicle_of_wheel[w] != static_cast<int>(k)) continue;
        if (static_cast<int>(k) == vehicle) pr->wheels.push_back(static_cast<int>(w));
        const int b = m.wheels[w].body;
        if (b >= 0 && std::find(bodies.begin(), bodies.end(), b) == bodies.end()) bodies.push_back(b);
      }
      pr->vbodies.push_back(std::move(bodies));
    }
    pr->bodies = pr->vbodies[static_cast<size_t>(vehicle)];
    g = std::move(pr);
    g_error.clear();
    return 0;
  } catch (const std::exception& e) {
    g_error = e.what();
    return -1;
  }
}

EMSCRIPTEN_KEEPALIVE const char* gs_error() { return g_error.c_str(); }
EMSCRIPTEN_KEEPALIVE double gs_dt() { return g ? g->sim->model().opt.dt : 0.0; }
EMSCRIPTEN_KEEPALIVE double gs_time() { return g ? g->sim->state().t : 0.0; }
EMSCRIPTEN_KEEPALIVE double gs_last_error() { return g_last_error; }
EMSCRIPTEN_KEEPALIVE int gs_road_car() { return g ? g->road_car : -1; }

EMSCRIPTEN_KEEPALIVE void gs_scale(double drive_torque, double brake_torque, double steer) {
  if (!g) return;
  g->drive_torque = drive_torque;
  g->brake_torque = brake_torque;
  g->steer = steer;
}

// The page's normalized controls, mapped as the bridge maps them
// (web/bridge/controls.cpp): a road car takes them as they are, other
// vehicles per-wheel torques and front steering.
EMSCRIPTEN_KEEPALIVE void gs_controls(double throttle, double brake, double steer, int handbrake, int gear) {
  if (!g) return;
  throttle = std::clamp(throttle, 0.0, 1.0);
  brake = std::clamp(brake, 0.0, 1.0);
  steer = std::clamp(steer, -1.0, 1.0);
  if (g->road_car >= 0) {
    CarControls c = g->sim->carControls(g->road_car);
    c.throttle = throttle;
    c.brake = brake;
    c.steer = steer;
    c.handbrake = handbrake != 0;
    c.gear = gear > 0 ? CarControls::kAuto : gear < 0 ? CarControls::kReverse : CarControls::kNeutral;
    g->sim->setCarControls(g->road_car, c);
    return;
  }
  const int n = static_cast<int>(g->wheels.size());
  const double dir = gear > 0 ? 1.0 : gear < 0 ? -1.0 : 0.0;
  for (int k = 0; k < n; ++k) {
    const bool front = n == 1 || k < 2;
    WheelControl& w = g->sim->controls()[static_cast<size_t>(g->wheels[static_cast<size_t>(k)])];
    w.drive_torque = dir * throttle * g->drive_torque;
    w.brake_torque = (handbrake && (!front || n == 1) ? 1.0 : brake) * g->brake_torque;
    w.steer = front && n > 1 ? steer * g->steer : 0.0;
  }
}

// n steps with the controls in force, each step's starting state saved.
// Returns 0, or -1 once the local run diverged (the page then re-creates).
EMSCRIPTEN_KEEPALIVE int gs_step(int n) {
  if (!g) return -1;
  for (int i = 0; i < n; ++i) {
    save(*g);
    if (!g->sim->step()) return -1;
    ++g->steps;
  }
  return 0;
}

// The predicted chassis: p[3], q[4] (w x y z), v[3], w[3] (world), as
// state_t carries them; a pointer into the module's memory (13 doubles).
EMSCRIPTEN_KEEPALIVE double* gs_pose() {
  if (!g) return g_pose;
  const VehicleSample s = sampleVehicle(*g->sim, g->vehicle, false);
  const double out[13] = {s.position.x(), s.position.y(), s.position.z(), s.orientation.w(), s.orientation.x(),
                          s.orientation.y(), s.orientation.z(), s.velocity.x(), s.velocity.y(), s.velocity.z(),
                          s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z()};
  std::copy(out, out + 13, g_pose);
  return g_pose;
}

// A server state at its time t: the chassis of every vehicle, 13 doubles
// each as gs_pose, count of them. When the ring holds the state at t: that
// state gets the server's chassis and the steps since are replayed with
// their recorded controls (returns how many; 0 when t is the present). The
// other cars are placed too and replayed with the controls the local run
// has for them (the scenario's: their drivers' are not known here), so they
// are where the server had them, carried on by the physics, not phantoms
// at their start. When t is ahead of the local run or older than the ring:
// the present state gets the server's chassis and the run's time becomes t
// (returns -1; the page steps it on).
EMSCRIPTEN_KEEPALIVE int gs_reconcile(double t, const double* poses, int count) {
  if (!g) return -1;
  Predictor& pr = *g;
  const Model& m = pr.sim->model();
  const double dt = m.opt.dt;
  if (count <= pr.vehicle) return -1;
  auto place = [&](State& s) {
    for (int k = 0; k < count && k < static_cast<int>(pr.vbodies.size()); ++k) {
      const double* pose = poses + 13 * k;
      const Vec3 p(pose[0], pose[1], pose[2]), v(pose[7], pose[8], pose[9]), w(pose[10], pose[11], pose[12]);
      const Quat q = Quat(pose[3], pose[4], pose[5], pose[6]).normalized();
      if (k == pr.vehicle) g_last_error = (Vec3(bodyPos(s.y, pr.bodies.front())) - p).norm();
      placeVehicle(m, s, pr.vbodies[static_cast<size_t>(k)], p, q, v, w);
    }
  };
  const double now_t = pr.sim->state().t;
  long long j = pr.steps - 1;
  // the state saved before the step starting nearest t (a rounding's slack)
  while (j >= pr.oldest && pr.ring[static_cast<size_t>(j % pr.kRing)].t > t + 0.5 * dt) --j;
  if (pr.steps > 0 && std::abs(t - now_t) <= 0.5 * dt) {  // t is the present
    State s = pr.sim->state();
    place(s);
    pr.sim->restore(s);
    return 0;
  }
  if (t > now_t || j < pr.oldest || pr.steps == 0) {
    State s = pr.sim->state();
    place(s);
    s.t = t;
    pr.sim->restore(s);
    pr.oldest = pr.steps;  // the saved states are of another timeline now
    return -1;
  }
  const long long now = pr.steps;
  State s = pr.ring[static_cast<size_t>(j % pr.kRing)];
  place(s);
  pr.sim->restore(s);
  pr.steps = j;
  for (long long k = j; k < now; ++k) {
    const State& rec = pr.ring[static_cast<size_t>(k % pr.kRing)];
    // the controls this step had when it was first taken
    State& cur = pr.sim->batchState();
    cur.controls = rec.controls;
    cur.car_controls = rec.car_controls;
    save(pr);
    if (!pr.sim->step()) return -2;
    ++pr.steps;
  }
  return static_cast<int>(now - j);
}

// The same scenario on another ground (the page's near grid of the ground,
// inline, in place of a ground this build cannot read: a PNG heightfield,
// an expression): the run goes on from its present state, saved states
// and all. 0 on success, else -1 and gs_error() says why.
EMSCRIPTEN_KEEPALIVE int gs_rebuild(const char* scenario_json) {
  if (!g) return -1;
  try {
    scenario::Scene scene = scenario::buildScene(scenario::parseScenario(std::string(scenario_json)));
    if (scene.built.model->stateSize() != g->sim->model().stateSize())
      throw std::runtime_error("the rebuilt scene's state does not match the run's");
    auto sim = std::make_unique<Simulator>(scene.built.model, scene.built.initial);
    sim->restore(g->sim->state());
    g->scene = std::move(scene);
    g->sim = std::move(sim);
    return 0;
  } catch (const std::exception& e) {
    g_error = e.what();
    return -1;
  }
}

// Back to the scenario's initial state (a session reset), at time t.
EMSCRIPTEN_KEEPALIVE void gs_reset(double t) {
  if (!g) return;
  State s = g->scene.built.initial;
  s.t = t;
  g->sim->restore(s);
  g->oldest = g->steps;
}

}  // extern "C"
