// A trained driver's laps on a race scenario against the classical
// driver's (docs/drivers.md, "Trained drivers"): vehicle 0 from the grid
// slot (start 0) and from held-out starts around it (start k: moved
// 1.5 sin(1.7 k) m along, 2 sin(2.3 k + 1) m across and 4 sin(3.1 k + 2)
// degrees, a fixed sequence no training episode used: training starts are
// drawn along the whole track from the environments' own streams), each
// driven by both until the race ends or time runs out. Prints per start:
// finished, laps, best lap, times off track, farthest from the line; then
// the success count (finished, never off track), the best laps of both
// drivers, the policy's evaluation cost per action and wall time.
// Run: build/bench/drivers/policy_laps SCENARIO POLICY [starts (default 10)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "drivers/lap_run.hpp"
#include "drivers/policy_driver.hpp"
#include "scenario/scenario.hpp"

namespace {

using namespace groundsim;

double best(const drivers::LapRun& r, bool circuit) {
  // a circuit's first lap starts standing on the grid: the best flying lap
  if (r.laps.empty()) return 0.0;
  if (!circuit || r.laps.size() < 2) return r.laps.front();
  return *std::min_element(r.laps.begin() + 1, r.laps.end());
}

void row(const char* who, int k, const drivers::LapRun& r, bool circuit) {
  std::printf("  start %2d %-9s %s laps %zu best %6.2f s race %7.2f s off track %d farthest %5.2f m%s%s\n", k, who,
              r.race_time > 0.0 ? "finished" : "DNF     ", r.laps.size(), best(r, circuit), r.race_time, r.off_track,
              r.worst_offset, r.healthy ? "" : " diverged: ", r.why.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: policy_laps SCENARIO POLICY [starts]\n");
    return 2;
  }
  const int starts = argc > 3 ? std::max(1, std::atoi(argv[3])) : 10;
  std::ifstream in(argv[2], std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  auto policy = std::make_shared<const drivers::Policy>(drivers::Policy::parse(text.str()));
  const scenario::Scenario base = scenario::loadScenarioFile(argv[1]);
  auto course = std::make_shared<const drivers::TrackCourse>(*base.race);
  const bool circuit = base.race->circuit;
  const double period = policy->controlPeriod() * policy->dt();
  std::printf("%s with %s (task %s, acting every %.3f s), %d starts\n", argv[1], argv[2], policy->task().c_str(),
              period, starts);
  int ok_policy = 0, ok_classical = 0;
  double best_policy = 1e9, best_classical = 1e9, wall = 0.0, acts = 0.0;
  for (int k = 0; k < starts; ++k) {
    scenario::Scenario s = base;
    CarPlacement& p = s.vehicles.at(0).placement;
    const double yaw = p.yaw, along = 1.5 * std::sin(1.7 * k), across = 2.0 * std::sin(2.3 * k + 1.0);
    p.position.x() += along * std::cos(yaw) - across * std::sin(yaw);
    p.position.y() += along * std::sin(yaw) + across * std::cos(yaw);
    p.yaw += 4.0 * std::sin(3.1 * k + 2.0) * std::numbers::pi / 180.0;
    const scenario::Scene scene = scenario::buildScene(s);
    drivers::PolicyDriver driver(policy, course, scene.built.model->road_cars.at(0).body);
    const auto t0 = std::chrono::steady_clock::now();
    const drivers::LapRun r = drivers::runDriver(s, scene, driver, period, 600.0);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    acts += (r.race_time > 0.0 ? r.race_time : 600.0) / period;
    const drivers::LapRun c = drivers::runClassical(s, scene, drivers::LapSetup{});
    row("trained", k, r, circuit);
    row("classical", k, c, circuit);
    const bool good = r.race_time > 0.0 && r.off_track == 0 && r.healthy;
    ok_policy += good ? 1 : 0;
    ok_classical += c.race_time > 0.0 && c.off_track == 0 && c.healthy ? 1 : 0;
    if (good) best_policy = std::min(best_policy, best(r, circuit));
    if (c.race_time > 0.0) best_classical = std::min(best_classical, best(c, circuit));
  }
  // the policy's own cost: one evaluation, timed over many
  std::vector<float> obs(static_cast<size_t>(policy->obsSize()), 0.1f), act(3);
  const int n = 200000;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) {
    obs[0] = static_cast<float>(i % 7);
    policy->act(obs.data(), act.data());
  }
  const double per_act = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / n;
  std::printf("trained: %d of %d starts finished without leaving the track; best %s %.2f s\n", ok_policy, starts,
              circuit ? "flying lap" : "run", ok_policy ? best_policy : 0.0);
  std::printf("classical: %d of %d; best %s %.2f s; trained / classical %.3f\n", ok_classical, starts,
              circuit ? "flying lap" : "run", best_classical, ok_policy ? best_policy / best_classical : 0.0);
  std::printf("policy evaluation %.2f us per action (%zu inputs), trained runs %.2f s wall for %.0f actions\n",
              per_act * 1e6, obs.size(), wall, acts);
  return 0;
}
