#include "drivers/lap_run.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "race/race.hpp"

namespace groundsim::drivers {

CarSense senseCar(const Model& m, const State& s, int car) {
  const int b = m.road_cars.at(static_cast<size_t>(car)).body;
  const Vec3 p = bodyPos(s.y, b);
  const Vec3 forward = Quat(bodyRot(s.y, b)).normalized() * Vec3::UnitX();
  CarSense c;
  c.position = {p.x(), p.y()};
  c.yaw = std::atan2(forward.y(), forward.x());
  c.speed = Vec3(bodyVel(s.y, b)).dot(forward);
  return c;
}

CarGeometry carGeometry(const Model& m, int car) {
  const RoadCarParams& p = m.road_cars.at(static_cast<size_t>(car)).p;
  return {p.wheelbase, p.steering.max_angle};
}

std::vector<double> frictionAlong(const Model& m, const TrackLine& line) {
  std::vector<double> mu(static_cast<size_t>(line.samples()));
  for (int i = 0; i < line.samples(); ++i) {
    const Vec2 q = line.pointAt(i * line.spacing());
    Vec3 point(q[0], q[1], 0.0), normal = Vec3::UnitZ();
    groundPointBelow(*m.ground, q[0], q[1], &point, &normal);
    mu[static_cast<size_t>(i)] = m.ground->friction(point, m.opt.contact.friction);
  }
  return mu;
}

namespace {

// Every road car's body centre (x, y), into `out` (sized once).
void positions(const Model& m, const State& s, std::vector<race::Vec2>& out) {
  out.resize(m.road_cars.size());
  for (size_t k = 0; k < m.road_cars.size(); ++k) {
    const Vec3 p = bodyPos(s.y, m.road_cars[k].body);
    out[k] = {p.x(), p.y()};
  }
}

}  // namespace

LapRun runClassical(const scenario::Scenario& scenario, const scenario::Scene& scene, const LapSetup& setup) {
  if (!scenario.race) throw std::invalid_argument("runClassical: the scenario has no race section");
  const Model& m = *scene.built.model;
  if (m.road_cars.empty()) throw std::invalid_argument("runClassical: the scenario has no road car");
  const scenario::RaceSpec& spec = *scenario.race;
  const TrackLine line(racingLine(spec), spec.circuit, 1.0);
  const SpeedProfile profile(line, setup.limits, frictionAlong(m, line));
  ClassicalBot driver(line, profile, m, 0, setup.tuning);
  LapRun run = runDriver(scenario, scene, driver, setup.control_period, setup.time_limit);
  run.profile_lap = profile.lapTime();
  return run;
}

LapRun runDriver(const scenario::Scenario& scenario, const scenario::Scene& scene, Driver& driver,
                 double control_period, double time_limit) {
  if (!scenario.race) throw std::invalid_argument("runDriver: the scenario has no race section");
  const Model& m = *scene.built.model;
  if (m.road_cars.empty()) throw std::invalid_argument("runDriver: the scenario has no road car");
  // 1. the line the offset is measured from
  const scenario::RaceSpec& spec = *scenario.race;
  const TrackLine line(racingLine(spec), spec.circuit, 1.0);
  LapRun run;
  run.line_length = line.length();
  double s = -1.0;
  // 2. the race, the other cars braked where they stand
  Simulator sim(scene.built.model, scene.built.initial);
  race::Race race(spec, static_cast<int>(m.road_cars.size()));
  CarControls parked;
  parked.brake = 1.0;
  for (size_t k = 0; k < m.road_cars.size(); ++k) sim.setCarControls(static_cast<int>(k), parked);
  const double dt = m.opt.dt;
  const long long per_control = std::max(1LL, std::llround(control_period / dt));
  const long long last = std::llround((race.goTime() + time_limit) / dt);
  // 3. step: the driver acts every control period once the race is on
  std::vector<race::Vec2> before, after;
  for (long long k = 0; k < last && run.race_time == 0.0; ++k) {
    const double t0 = sim.state().t;
    if (k % per_control == 0 && !race.held(t0)) {
      sim.setCarControls(0, toControls(driver.drive(m, sim.state())));
      const Vec3 at = bodyPos(sim.state().y, m.road_cars[0].body);
      const TrackLine::Where w = line.locate({at.x(), at.y()}, s);
      s = w.s;
      if (race.standing(0).started) run.worst_offset = std::max(run.worst_offset, std::abs(w.offset));
    }
    positions(m, sim.state(), before);
    if (!sim.step()) {
      run.healthy = false;
      run.why = sim.state().health_reason;
      break;
    }
    positions(m, sim.state(), after);
    for (const race::RaceEvent& e : race.step(t0, sim.state().t, before, after)) {
      if (e.car != 0) continue;
      if (e.kind == race::EventKind::Lap) run.laps.push_back(e.time);
      if (e.kind == race::EventKind::Finish) run.race_time = e.time;
      if (e.kind == race::EventKind::OffTrack && e.on) ++run.off_track;
    }
  }
  return run;
}

}  // namespace groundsim::drivers
