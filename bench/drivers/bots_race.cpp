// Races of bots (docs/drivers.md, "Bots in sessions"): `cars` cars on a
// race's grid, every one driven by the trained policy (or the classical
// driver: POLICY "classical"), in `races` races whose starts differ by a
// fixed sequence of small offsets (race k moves car c by
// 0.5 sin(1.3 k + c) m along, 0.4 sin(2.1 k + 3 c) m across, as
// policy_laps' held-out starts). Steps the scene as a session does (all
// cars, contact between them, each bot acting every control period) and
// prints per race: laps completed, hits between cars (a pair's contact
// that begins; a session counts the same as a "hit" event), hits with
// walls and objects; then the averages, the simulation's real-time factor
// (simulated s per wall s, on one core) and the share of the wall time
// spent evaluating the bots' policies.
// Each bot keeps the traffic rules (drivers/traffic.hpp) unless the last
// argument is "alone".
// Run: build/bench/drivers/bots_race SCENARIO POLICY|classical [cars (default 4)] [races (default 10)] [seconds (default 60)] [alone]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "drivers/lap_run.hpp"
#include "drivers/policy_driver.hpp"
#include "drivers/traffic.hpp"
#include "race/race.hpp"
#include "scenario/bots_override.hpp"
#include "scenario/scenario.hpp"

int main(int argc, char** argv) {
  using namespace groundsim;
  using Clock = std::chrono::steady_clock;
  if (argc < 3) {
    std::fprintf(stderr, "usage: bots_race SCENARIO POLICY|classical [cars] [races] [seconds]\n");
    return 2;
  }
  const std::string path = argv[1], which = argv[2];
  const int cars = argc > 3 ? std::clamp(std::atoi(argv[3]), 1, 8) : 4;
  const int races = argc > 4 ? std::max(1, std::atoi(argv[4])) : 10;
  const double seconds = argc > 5 ? std::atof(argv[5]) : 60.0;
  const bool traffic = !(argc > 6 && std::string(argv[6]) == "alone");
  // BOTS_RACE_IDLE_FIRST=1: car 0 stays braked on its slot, as a player who never drives
  const bool idle_first = std::getenv("BOTS_RACE_IDLE_FIRST") != nullptr;
  std::shared_ptr<const drivers::Policy> policy;
  if (which != "classical") {
    std::ifstream in(which, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    policy = std::make_shared<const drivers::Policy>(drivers::Policy::parse(text.str()));
  }
  nlohmann::json doc = scenario::loadScenarioDocument(path, scenario::Budget{});
  scenario::setBots(doc, {cars - 1, std::nullopt, std::nullopt});  // car 0 and cars - 1 bots: all driven here
  const std::string dir = std::filesystem::path(path).parent_path().string();
  std::printf("%s: %d cars driven by %s%s, %d races of %.0f s\n", path.c_str(), cars, which.c_str(),
              traffic ? " with the traffic rules" : " alone (no traffic rules)", races, seconds);
  double total_car_hits = 0.0, total_wall_hits = 0.0, total_laps = 0.0, sim_time = 0.0, wall = 0.0, policy_wall = 0.0;
  for (int k = 0; k < races; ++k) {
    nlohmann::json d = doc;
    scenario::Scenario s = scenario::parseScenario(d, scenario::Budget{}, scenario::FileAccess::local(dir));
    for (int c = 0; c < cars; ++c) {
      CarPlacement& p = s.vehicles.at(static_cast<size_t>(c)).placement;
      const double along = 0.5 * std::sin(1.3 * k + c), across = 0.4 * std::sin(2.1 * k + 3 * c);
      p.position.x() += along * std::cos(p.yaw) - across * std::sin(p.yaw);
      p.position.y() += along * std::sin(p.yaw) + across * std::cos(p.yaw);
    }
    const scenario::Scene scene = scenario::buildScene(s);
    const Model& m = *scene.built.model;
    Simulator sim(scene.built.model, scene.built.initial);
    race::Race race(*s.race, static_cast<int>(m.road_cars.size()));
    // the drivers
    auto course = std::make_shared<const drivers::TrackCourse>(*s.race);
    const drivers::TrackLine line(drivers::racingLine(*s.race), s.race->circuit, 1.0);
    const drivers::SpeedProfile profile(line, drivers::CarLimits{}, drivers::frictionAlong(m, line));
    std::vector<std::unique_ptr<drivers::Driver>> bots;
    for (int c = 0; c < cars; ++c) {
      std::unique_ptr<drivers::Driver> d;
      if (policy) d = std::make_unique<drivers::PolicyDriver>(policy, course, m.road_cars[c].body);
      else d = std::make_unique<drivers::ClassicalBot>(line, profile, m, c);
      if (traffic) {
        std::vector<int> others;
        for (int o = 0; o < cars; ++o)
          if (o != c) others.push_back(m.road_cars[static_cast<size_t>(o)].body);
        drivers::TrafficRules rules;
        rules.steer_clear = !std::getenv("BOTS_RACE_NO_STEER");
        d = std::make_unique<drivers::TrafficAware>(std::move(d), m.road_cars[c].body, others, c, rules);
      }
      bots.push_back(std::move(d));
    }
    const double period = policy ? policy->controlPeriod() * policy->dt() : 0.02;
    const long long per = std::max(1LL, std::llround(period / m.opt.dt));
    const long long last = std::llround((race.goTime() + seconds) / m.opt.dt);
    CarControls held;
    held.brake = 1.0;
    for (int c = 0; c < cars; ++c) sim.setCarControls(c, held);
    std::vector<race::Vec2> before(m.road_cars.size()), after(m.road_cars.size());
    auto positions = [&](std::vector<race::Vec2>& out) {
      for (size_t c = 0; c < m.road_cars.size(); ++c) {
        const Vec3 p = bodyPos(sim.state().y, m.road_cars[c].body);
        out[c] = {p.x(), p.y()};
      }
    };
    int car_hits = 0, wall_hits = 0, laps = 0;
    std::vector<int> car_laps(static_cast<size_t>(cars), 0);
    constexpr double kApart = 0.5;  // s
    std::map<std::pair<int, int>, double> last_contact;
    const auto t0 = Clock::now();
    for (long long step = 0; step < last; ++step) {
      const double t = sim.state().t;
      if (step % per == 0 && !race.held(t)) {
        const auto p0 = Clock::now();
        for (int c = idle_first ? 1 : 0; c < cars; ++c) {
          sim.setCarControls(c, drivers::toControls(bots[static_cast<size_t>(c)]->drive(m, sim.state())));
        }
        policy_wall += std::chrono::duration<double>(Clock::now() - p0).count();
      }
      positions(before);
      if (!sim.step()) {
        std::printf("  race %d: diverged: %s\n", k, sim.state().health_reason.c_str());
        break;
      }
      positions(after);
      for (const race::RaceEvent& e : race.step(t, sim.state().t, before, after))
        if (e.kind == race::EventKind::Lap) ++laps, ++car_laps[static_cast<size_t>(e.car)];
      // a hit: a pair's contact that begins (its first step) more than
      // kApart after the pair's last contact ended (a scrape that flickers
      // between steps is one hit)
      for (const Hit& h : sim.hits()) {
        const auto key = std::make_pair(h.a, h.b);
        const auto it = last_contact.find(key);
        const bool fresh = h.begin == h.end && (it == last_contact.end() || h.begin - it->second > kApart);
        last_contact[key] = h.end;
        if (!fresh) continue;
        const int va = m.groups[h.a].vehicle, vb = m.groups[h.b].vehicle;
        if (va >= 0 && vb >= 0 && va != vb) {
          ++car_hits;
          if (std::getenv("BOTS_RACE_VERBOSE"))
            std::printf("    hit at %.2f s: cars %d and %d, closing %.2f m/s, at (%.1f, %.1f)\n", h.begin, va, vb,
                        h.closing_speed, h.where.x(), h.where.y());
        }
        else if (va >= 0 || vb >= 0) ++wall_hits;
      }
    }
    const double w = std::chrono::duration<double>(Clock::now() - t0).count();
    wall += w;
    sim_time += sim.state().t;
    total_car_hits += car_hits;
    total_wall_hits += wall_hits;
    total_laps += laps;
    std::string each;
    for (int l : car_laps) each += (each.empty() ? "" : " ") + std::to_string(l);
    if (std::getenv("BOTS_RACE_VERBOSE"))
      for (int c = 0; c < cars; ++c) {
        const Vec3 q = bodyPos(sim.state().y, m.road_cars[static_cast<size_t>(c)].body);
        std::printf("    car %d ends at (%.1f, %.1f) at %.1f m/s\n", c, q.x(), q.y(),
                    Vec3(bodyVel(sim.state().y, m.road_cars[static_cast<size_t>(c)].body)).norm());
      }
    std::printf("  race %2d: laps %d (car by car: %s), hits between cars %d, with walls and objects %d, %.2f s wall\n",
                k, laps, each.c_str(), car_hits, wall_hits, w);
  }
  std::printf("mean per race: hits between cars %.2f, with walls and objects %.2f, laps %.1f\n",
              total_car_hits / races, total_wall_hits / races, total_laps / races);
  std::printf("real-time factor %.1fx on one core (%.0f simulated s in %.2f wall s); drivers' share %.2f%% of the wall time\n",
              sim_time / wall, sim_time, wall, 100.0 * policy_wall / wall);
  return 0;
}
