// Session <-> race (race_glue.hpp): holds cars during the countdown, feeds
// the race each step's positions, publishes its happenings as events
// ("race: {json}", docs/protocol.md, Race events) and respawns cars.
#include "stepping/race_glue.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "physics/ground/ground.hpp"
#include "scenario/scenario.hpp"
#include "stepping/applied.hpp"

namespace groundsim::stepping {
namespace {

// brake torque (N m) holding a report car's wheels before go
constexpr double kHoldBrakeTorque = 1e4;
// a respawn spot is free when no other car's centre is this close (m)
constexpr double kRespawnClearance = 4.0;
constexpr double kRespawnLateralStep = 3.0;  // m along the gate between tries
// a protection ends only once its car is clear of every other: no other
// car's centre within this box about it (a sedan's 4.8 x 1.8 m and a
// margin); until then it is looked at again every kProtectionRecheck
constexpr double kClearLength = 5.0;       // m, half the box's length plus half a car's
constexpr double kClearWidth = 2.4;        // m
constexpr double kProtectionRecheck = 0.1; // s
// dropped from this much above its resting height (on a slope the lower
// wheel would otherwise start in the ground)
constexpr double kRespawnDrop = 0.05;        // m

race::Vec2 centre(const Simulator& sim, int v) {
  const Vec3 p = bodyPos(sim.state().y, sim.model().vehicle_body.at(static_cast<std::size_t>(v)));
  return {p.x(), p.y()};
}

double groundZ(const Ground& g, double x, double y, double fallback) {
  Vec3 surface, normal;
  return groundPointBelow(g, x, y, &surface, &normal) ? surface.z() : fallback;
}

// A road car's pedals set, its other controls kept (other vehicles: nothing).
void setPedals(Simulator& sim, int v, double throttle, double brake) {
  const int c = sim.roadCarIndex(v);
  if (c < 0) return;
  CarControls cc = sim.carControls(c);
  cc.throttle = throttle;
  cc.brake = brake;
  sim.setCarControls(c, cc);
}

double yawOf(const Quat& q) {
  const Vec3 f = q * Vec3::UnitX();
  return std::atan2(f.y(), f.x());
}

}  // namespace

std::unique_ptr<RaceGlue> makeRaceGlue(const std::string& scenario_json, std::shared_ptr<const Model> m) {
  if (scenario_json.find("\"race\"") == std::string::npos) return nullptr;  // no JSON parse for most sessions
  std::optional<scenario::RaceSpec> spec;
  try {
    spec = scenario::readRaceSection(nlohmann::json::parse(scenario_json));
  } catch (const std::exception&) {
    return nullptr;  // validated at create: not reached
  }
  if (!spec) return nullptr;
  const int cars = static_cast<int>(m->vehicle_names.size());
  return std::make_unique<RaceGlue>(std::move(*spec), cars, std::move(m));
}

std::shared_ptr<const Model> ghostModel(const Model& m, const std::vector<bool>& ghost) {
  auto g = std::make_shared<Model>(m);
  for (CollisionGroup& grp : g->groups)
    if (grp.vehicle >= 0 && static_cast<std::size_t>(grp.vehicle) < ghost.size() && ghost[static_cast<std::size_t>(grp.vehicle)]) {
      grp.probe_end = grp.probe_begin;
      grp.collider_end = grp.collider_begin;
    }
  return g;
}

void placeVehicle(Simulator& sim, const State& initial, int v, double x, double y, double yaw) {
  const Model& m = sim.model();
  const int chassis = m.vehicle_body.at(static_cast<std::size_t>(v));
  std::set<int> bodies{chassis};
  std::set<int> wheels;
  for (std::size_t w = 0; w < m.wheels.size(); ++w)
    if (m.vehicle_of_wheel[w] == v) {
      wheels.insert(static_cast<int>(w));
      if (m.wheels[w].body >= 0) bodies.insert(m.wheels[w].body);
      if (m.wheels[w].carrier >= 0) bodies.insert(m.wheels[w].carrier);
    }
  const Vec3 p0 = bodyPos(initial.y, chassis);
  const double yaw0 = yawOf(Quat(bodyRot(initial.y, chassis)).normalized());
  const Quat turn(Eigen::AngleAxisd(yaw - yaw0, Vec3::UnitZ()));
  const Ground& g = *m.ground;
  const double z = p0.z() + groundZ(g, x, y, 0.0) - groundZ(g, p0.x(), p0.y(), 0.0) + kRespawnDrop;
  const Vec3 target(x, y, z);

  const double e_before = sim.energy().total();
  State s = sim.state();
  for (int b : bodies) {
    bodyPos(s.y, b) = target + turn * (Vec3(bodyPos(initial.y, b)) - p0);
    bodyRot(s.y, b) = (turn * Quat(bodyRot(initial.y, b))).normalized();
    bodyVel(s.y, b).setZero();
    bodyMom(s.y, b).setZero();
  }
  const int nb = static_cast<int>(m.bodies.size());
  for (std::size_t j = 0; j < m.particles.size(); ++j) {
    const Point& pt = m.points[static_cast<std::size_t>(m.particle_points[j])];
    if (pt.wheel < 0 || !wheels.count(pt.wheel)) continue;
    const int o = particleOffset(nb, static_cast<int>(j));
    const Vec3 q0(initial.y[o], initial.y[o + 1], initial.y[o + 2]);
    const Vec3 q = target + turn * (q0 - p0);
    for (int i = 0; i < 3; ++i) {
      s.y[o + i] = q[i];
      s.y[o + 3 + i] = 0.0;
    }
  }
  const int c = sim.roadCarIndex(v);
  if (c >= 0) {  // the car's own states (suspension, spins, engine) as on the grid, at rest
    const RoadCar& rc = m.road_cars[static_cast<std::size_t>(c)];
    for (int i = 0; i < kRoadCarStates; ++i) s.y[m.auxBase() + rc.aux + i] = initial.y[m.auxBase() + rc.aux + i];
    for (int w = 0; w < 4; ++w) {  // at rest: no strut speed, no wheel spin
      s.y[m.auxBase() + rc.aux + roadAux(w, 1)] = 0.0;
      s.y[m.auxBase() + rc.aux + roadAux(w, 2)] = 0.0;
    }
    s.cars[static_cast<std::size_t>(c)] = initial.cars.at(static_cast<std::size_t>(c));
  }
  sim.restore(s);
  // the energy check compares with the initial energy plus drive work: a
  // car put back higher up gained no energy from the simulation
  s.initial_energy += sim.energy().total() - e_before;
  sim.restore(s);
}

// ---- a race's effect on the simulation --------------------------------------

void raceHold(RaceGlue& g, Simulator& sim) {
  const int n = g.race.cars();
  g.before.resize(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) g.before[static_cast<std::size_t>(v)] = centre(sim, v);
  if (!g.race.held(sim.state().t)) return;
  // the countdown: no throttle, brakes on, whatever a driver sends
  for (int v = 0; v < n; ++v) setPedals(sim, v, 0.0, 1.0);
  const Model& m = sim.model();
  for (std::size_t w = 0; w < m.wheels.size(); ++w) {
    if (m.vehicle_of_wheel[w] < 0) continue;
    sim.controls()[w].drive_torque = 0.0;
    sim.controls()[w].brake_torque = kHoldBrakeTorque;
  }
}

void raceGhosts(RaceGlue& g, Simulator& sim) {
  const double t = sim.state().t;
  std::vector<bool> ghost(g.ghost_until.size(), false);
  bool any = false;
  for (std::size_t v = 0; v < ghost.size(); ++v) any |= ghost[v] = t < g.ghost_until[v];
  if (!any && !g.ghosted) return;
  State s = sim.state();
  sim = Simulator(any ? ghostModel(*g.model, ghost) : g.model, std::move(s));
  g.ghosted = any;
}

nlohmann::json raceProgress(const RaceGlue& g) {
  return {{"race", g.race.progress()}, {"announced", g.announced}, {"ghost_until", g.ghost_until}};
}

std::string raceRestore(RaceGlue& g, Simulator& sim, const nlohmann::json& j) {
  try {
    std::vector<double> ghost_until = j.at("ghost_until").get<std::vector<double>>();
    if (ghost_until.size() != g.ghost_until.size()) return "the race's protections are of another number of cars";
    if (std::string why = g.race.restore(j.at("race")); !why.empty()) return why;
    g.announced = j.at("announced").get<bool>();
    g.ghost_until = std::move(ghost_until);
    raceGhosts(g, sim);
    return "";
  } catch (const std::exception& e) {
    return std::string("the race's progress: ") + e.what();
  }
}

// Whether vehicle v's car overlaps another's (a centre inside the clear box about it).
bool overlapsAnother(const Simulator& sim, int v, int cars) {
  const State& s = sim.state();
  const int body = sim.model().vehicle_body.at(static_cast<std::size_t>(v));
  const Mat3 R = bodyRot(s.y, body).normalized().toRotationMatrix();
  const Vec3 c = bodyPos(s.y, body);
  for (int o = 0; o < cars; ++o) {
    if (o == v) continue;
    const Vec3 d = R.transpose() * Vec3(bodyPos(s.y, sim.model().vehicle_body.at(static_cast<std::size_t>(o))) - c);
    if (std::abs(d.x()) < kClearLength && std::abs(d.y()) < kClearWidth) return true;
  }
  return false;
}

std::vector<race::RaceEvent> raceStepped(RaceGlue& g, Simulator& sim, double t0) {
  if (g.ghosted) {  // protections that end now: those of cars clear of the others (a car still in another stays a ghost)
    bool over = false;
    const double t = sim.state().t;
    for (std::size_t v = 0; v < g.ghost_until.size(); ++v) {
      double& until = g.ghost_until[v];
      if (!(until > 0.0 && until <= t && until > t0)) continue;
      if (overlapsAnother(sim, static_cast<int>(v), g.race.cars())) {
        until = t + kProtectionRecheck;
        g.race.extendProtection(static_cast<int>(v), until);
      } else {
        over = true;
      }
    }
    if (over) raceGhosts(g, sim);
  }
  const bool was_held = g.race.held(t0);
  const int n = g.race.cars();
  g.after.resize(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) g.after[static_cast<std::size_t>(v)] = centre(sim, v);
  std::vector<race::RaceEvent> happened = g.race.step(t0, sim.state().t, g.before, g.after);
  if (was_held && !g.race.held(sim.state().t)) {
    // go: the brakes the countdown held come off (a driver's next controls set them)
    releasePedals(sim);
    releaseDrive(sim);
  }
  return happened;
}

void raceRestart(RaceGlue& g, Simulator& sim) {
  g.race.reset();
  g.announced = false;
  std::fill(g.ghost_until.begin(), g.ghost_until.end(), 0.0);
  raceGhosts(g, sim);
}

std::vector<race::RaceEvent> raceRespawnCar(RaceGlue& g, Simulator& sim, const State& initial, int car) {
  race::Pose pose;
  if (auto p = g.race.respawnPose(car)) {
    pose = *p;
  } else {  // no gate passed and no grid: where it started
    const int body = sim.model().vehicle_body.at(static_cast<std::size_t>(car));
    const Vec3 p0 = bodyPos(initial.y, body);
    pose.position = {p0.x(), p0.y()};
    pose.yaw = yawOf(Quat(bodyRot(initial.y, body)).normalized());
  }
  // a spot clear of the other cars: the gate's centre, else along the gate line
  const double lx = -std::sin(pose.yaw), ly = std::cos(pose.yaw);
  race::Vec2 spot = pose.position;
  for (int i = 0; i < 9; ++i) {
    const double off = kRespawnLateralStep * ((i + 1) / 2) * (i % 2 ? 1.0 : -1.0);
    const race::Vec2 cand{pose.position[0] + off * lx, pose.position[1] + off * ly};
    bool clear = true;
    for (int o = 0; o < g.race.cars() && clear; ++o)
      if (o != car) {
        const race::Vec2 c = centre(sim, o);
        clear = std::hypot(c[0] - cand[0], c[1] - cand[1]) >= kRespawnClearance;
      }
    if (clear) {
      spot = cand;
      break;
    }
  }
  placeVehicle(sim, initial, car, spot[0], spot[1], pose.yaw);
  setPedals(sim, car, 0.0, 0.0);
  pose.position = spot;
  std::vector<race::RaceEvent> happened = g.race.respawned(car, pose, sim.state().t);
  // protected: it passes through the others until then (contact between bodies only)
  if (sim.model().collisions && g.race.spec().respawn_protection > 0.0) {
    g.ghost_until[static_cast<std::size_t>(car)] = sim.state().t + g.race.spec().respawn_protection;
    raceGhosts(g, sim);
  }
  return happened;
}

}  // namespace groundsim::stepping
