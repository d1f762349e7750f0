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
#include <optional>
#include <sstream>
#include <string>

#include "drivers/lap_run.hpp"
#include "drivers/policy_driver.hpp"
#include "drivers/traffic.hpp"
#include "race/race.hpp"
#include "scenario/bots_override.hpp"
#include "scenario/scenario.hpp"

namespace {

using namespace groundsim;
using Clock = std::chrono::steady_clock;

// The command line and the environment's switches.
struct CommandLine {
  std::string path, which;
  int cars = 4, races = 10;
  double seconds = 60.0;
  bool traffic = true;
  bool idle_first = false;  // BOTS_RACE_IDLE_FIRST=1: car 0 stays braked on its slot, as a player who never drives
};

std::optional<CommandLine> parseOptions(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bots_race SCENARIO POLICY|classical [cars] [races] [seconds]\n");
    return std::nullopt;
  }
  CommandLine o;
  o.path = argv[1];
  o.which = argv[2];
  o.cars = argc > 3 ? std::clamp(std::atoi(argv[3]), 1, 8) : 4;
  o.races = argc > 4 ? std::max(1, std::atoi(argv[4])) : 10;
  o.seconds = argc > 5 ? std::atof(argv[5]) : 60.0;
  o.traffic = !(argc > 6 && std::string(argv[6]) == "alone");
  o.idle_first = std::getenv("BOTS_RACE_IDLE_FIRST") != nullptr;
  return o;
}

// The trained policy, none for "classical".
std::shared_ptr<const drivers::Policy> loadPolicy(const std::string& which) {
  if (which == "classical") return nullptr;
  std::ifstream in(which, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return std::make_shared<const drivers::Policy>(drivers::Policy::parse(text.str()));
}

nlohmann::json loadDocument(const CommandLine& o) {
  nlohmann::json doc = scenario::loadScenarioDocument(o.path, scenario::Budget{});
  scenario::setBots(doc, {o.cars - 1, std::nullopt, std::nullopt});  // car 0 and cars - 1 bots: all driven here
  return doc;
}

void printHeader(const CommandLine& o) {
  std::printf("%s: %d cars driven by %s%s, %d races of %.0f s\n", o.path.c_str(), o.cars, o.which.c_str(),
              o.traffic ? " with the traffic rules" : " alone (no traffic rules)", o.races, o.seconds);
}

// The scenario with race k's grid: car c moved 0.5 sin(1.3 k + c) m along,
// 0.4 sin(2.1 k + 3 c) m across.
scenario::Scenario movedGrid(const nlohmann::json& doc, const std::string& dir, int cars, int k) {
  scenario::Scenario s = scenario::parseScenario(doc, scenario::Budget{}, scenario::FileAccess::local(dir));
  for (int c = 0; c < cars; ++c) {
    CarPlacement& p = s.vehicles.at(static_cast<size_t>(c)).placement;
    const double along = 0.5 * std::sin(1.3 * k + c), across = 0.4 * std::sin(2.1 * k + 3 * c);
    p.position.x() += along * std::cos(p.yaw) - across * std::sin(p.yaw);
    p.position.y() += along * std::sin(p.yaw) + across * std::cos(p.yaw);
  }
  return s;
}

// Car c's driver: the policy or the classical driver, in the traffic rules
// unless alone.
std::unique_ptr<drivers::Driver> makeBot(const CommandLine& o, const std::shared_ptr<const drivers::Policy>& policy,
                                         const std::shared_ptr<const drivers::TrackCourse>& course,
                                         const drivers::TrackLine& line, const drivers::SpeedProfile& profile,
                                         const Model& m, int c) {
  std::unique_ptr<drivers::Driver> d;
  if (policy) d = std::make_unique<drivers::PolicyDriver>(policy, course, m.road_cars[c].body);
  else d = std::make_unique<drivers::ClassicalBot>(line, profile, m, c);
  if (!o.traffic) return d;
  std::vector<int> others;
  for (int other = 0; other < o.cars; ++other)
    if (other != c) others.push_back(m.road_cars[static_cast<size_t>(other)].body);
  drivers::TrafficRules rules;
  rules.steer_clear = !std::getenv("BOTS_RACE_NO_STEER");
  return std::make_unique<drivers::TrafficAware>(std::move(d), m.road_cars[c].body, others, c, rules);
}

// One race: its scene, simulator and race rules, the drivers' line and
// speed profile (the classical bots keep references to them: built in
// place, never moved), the bots, and the stepping's periods in steps.
struct RaceSetup {
  scenario::Scenario s;
  scenario::Scene scene;
  const Model& m;
  Simulator sim;
  race::Race race;
  std::shared_ptr<const drivers::TrackCourse> course;
  drivers::TrackLine line;
  drivers::SpeedProfile profile;
  std::vector<std::unique_ptr<drivers::Driver>> bots;
  long long per = 1;   // steps between the bots' actions
  long long last = 0;  // steps in the race

  RaceSetup(const CommandLine& o, const std::shared_ptr<const drivers::Policy>& policy, const nlohmann::json& doc,
            const std::string& dir, int k)
      : s(movedGrid(doc, dir, o.cars, k)),
        scene(scenario::buildScene(s)),
        m(*scene.built.model),
        sim(scene.built.model, scene.built.initial),
        race(*s.race, static_cast<int>(m.road_cars.size())),
        course(std::make_shared<const drivers::TrackCourse>(*s.race)),
        line(drivers::racingLine(*s.race), s.race->circuit, 1.0),
        profile(line, drivers::CarLimits{}, drivers::frictionAlong(m, line)) {
    for (int c = 0; c < o.cars; ++c) bots.push_back(makeBot(o, policy, course, line, profile, m, c));
    const double period = policy ? policy->controlPeriod() * policy->dt() : 0.02;
    per = std::max(1LL, std::llround(period / m.opt.dt));
    last = std::llround((race.goTime() + o.seconds) / m.opt.dt);
    CarControls held;
    held.brake = 1.0;
    for (int c = 0; c < o.cars; ++c) sim.setCarControls(c, held);
  }
};

// What one race counted.
struct RaceResult {
  int car_hits = 0, wall_hits = 0, laps = 0;
  std::vector<int> car_laps;  // by car
  double wall = 0.0;          // s of wall time
};

// A hit: a pair's contact that begins (its first step) more than kApart
// after the pair's last contact ended (a scrape that flickers between steps
// is one hit).
class HitCounter {
 public:
  void count(const Model& m, const std::vector<Hit>& hits, RaceResult& r) {
    for (const Hit& h : hits) {
      const auto key = std::make_pair(h.a, h.b);
      const auto it = last_contact_.find(key);
      const bool fresh = h.begin == h.end && (it == last_contact_.end() || h.begin - it->second > kApart);
      last_contact_[key] = h.end;
      if (!fresh) continue;
      const int va = m.groups[h.a].vehicle, vb = m.groups[h.b].vehicle;
      if (va >= 0 && vb >= 0 && va != vb) {
        ++r.car_hits;
        if (std::getenv("BOTS_RACE_VERBOSE"))
          std::printf("    hit at %.2f s: cars %d and %d, closing %.2f m/s, at (%.1f, %.1f)\n", h.begin, va, vb,
                      h.closing_speed, h.where.x(), h.where.y());
      }
      else if (va >= 0 || vb >= 0) ++r.wall_hits;
    }
  }

 private:
  static constexpr double kApart = 0.5;  // s
  std::map<std::pair<int, int>, double> last_contact_;
};

void positions(const RaceSetup& r, std::vector<race::Vec2>& out) {
  for (size_t c = 0; c < r.m.road_cars.size(); ++c) {
    const Vec3 p = bodyPos(r.sim.state().y, r.m.road_cars[c].body);
    out[c] = {p.x(), p.y()};
  }
}

// Every bot (but an idle car 0) acts; its wall time added to policy_wall.
void driveBots(RaceSetup& r, const CommandLine& o, double& policy_wall) {
  const auto p0 = Clock::now();
  for (int c = o.idle_first ? 1 : 0; c < o.cars; ++c) {
    r.sim.setCarControls(c, drivers::toControls(r.bots[static_cast<size_t>(c)]->drive(r.m, r.sim.state())));
  }
  policy_wall += std::chrono::duration<double>(Clock::now() - p0).count();
}

// Steps race k to its end (or its divergence), counting laps and hits.
RaceResult runRace(RaceSetup& r, const CommandLine& o, int k, double& policy_wall) {
  RaceResult result;
  result.car_laps.assign(static_cast<size_t>(o.cars), 0);
  std::vector<race::Vec2> before(r.m.road_cars.size()), after(r.m.road_cars.size());
  HitCounter hits;
  const auto t0 = Clock::now();
  for (long long step = 0; step < r.last; ++step) {
    const double t = r.sim.state().t;
    if (step % r.per == 0 && !r.race.held(t)) driveBots(r, o, policy_wall);
    positions(r, before);
    if (!r.sim.step()) {
      std::printf("  race %d: diverged: %s\n", k, r.sim.state().health_reason.c_str());
      break;
    }
    positions(r, after);
    for (const race::RaceEvent& e : r.race.step(t, r.sim.state().t, before, after))
      if (e.kind == race::EventKind::Lap) ++result.laps, ++result.car_laps[static_cast<size_t>(e.car)];
    hits.count(r.m, r.sim.hits(), result);
  }
  result.wall = std::chrono::duration<double>(Clock::now() - t0).count();
  return result;
}

// The sums over the races.
struct Totals {
  double car_hits = 0.0, wall_hits = 0.0, laps = 0.0, sim_time = 0.0, wall = 0.0, policy_wall = 0.0;

  void add(const RaceResult& r, double simulated) {
    wall += r.wall;
    sim_time += simulated;
    car_hits += r.car_hits;
    wall_hits += r.wall_hits;
    laps += r.laps;
  }
};

void printRace(const RaceSetup& r, const CommandLine& o, int k, const RaceResult& result) {
  std::string each;
  for (int l : result.car_laps) each += (each.empty() ? "" : " ") + std::to_string(l);
  if (std::getenv("BOTS_RACE_VERBOSE"))
    for (int c = 0; c < o.cars; ++c) {
      const int body = r.m.road_cars[static_cast<size_t>(c)].body;
      const Vec3 q = bodyPos(r.sim.state().y, body);
      std::printf("    car %d ends at (%.1f, %.1f) at %.1f m/s\n", c, q.x(), q.y(),
                  Vec3(bodyVel(r.sim.state().y, body)).norm());
    }
  std::printf("  race %2d: laps %d (car by car: %s), hits between cars %d, with walls and objects %d, %.2f s wall\n",
              k, result.laps, each.c_str(), result.car_hits, result.wall_hits, result.wall);
}

void printSummary(const Totals& t, int races) {
  std::printf("mean per race: hits between cars %.2f, with walls and objects %.2f, laps %.1f\n",
              t.car_hits / races, t.wall_hits / races, t.laps / races);
  std::printf("real-time factor %.1fx on one core (%.0f simulated s in %.2f wall s); drivers' share %.2f%% of the wall time\n",
              t.sim_time / t.wall, t.sim_time, t.wall, 100.0 * t.policy_wall / t.wall);
}

}  // namespace

int main(int argc, char** argv) {
  const std::optional<CommandLine> o = parseOptions(argc, argv);
  if (!o) return 2;
  const std::shared_ptr<const drivers::Policy> policy = loadPolicy(o->which);
  const nlohmann::json doc = loadDocument(*o);
  const std::string dir = std::filesystem::path(o->path).parent_path().string();
  printHeader(*o);
  Totals totals;
  for (int k = 0; k < o->races; ++k) {
    RaceSetup race(*o, policy, doc, dir, k);
    const RaceResult result = runRace(race, *o, k, totals.policy_wall);
    totals.add(result, race.sim.state().t);
    printRace(race, *o, k, result);
  }
  printSummary(totals, o->races);
  return 0;
}
