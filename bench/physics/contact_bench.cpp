// The cost of contact between bodies when nothing touches (issue 19): 32
// road cars spread over the hills heightfield, with collisions on and off,
// and the same for 4 of the report's cars at the fast preset on a plane
// (the specialised kernel while no pair may touch; it takes at most 16
// wheels). The broad phase must
// stay within 5% of "off". Also cars close but apart, as in a race: 8
// sedans in two lanes 4.2 m apart, 12 m nose to nose, whose bounding
// spheres overlap but whose boxes do not.
// Run: build/bench/physics/contact_bench.
#include <benchmark/benchmark.h>

#include <string>

#include <nlohmann/json.hpp>

#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim {
namespace {

scenario::Scene fleet(bool road_cars, bool collisions) {
  const int count = road_cars ? 32 : 4;
  nlohmann::json doc = scenario::loadScenarioDocument(std::string(GROUNDSIM_CONFIGS) + "/hills.json");
  doc.erase("vehicle");
  doc["name"] = "fleet";
  doc["duration"] = 1e4;
  doc["collisions"] = {{"enabled", collisions}};
  if (road_cars) {
    doc["physics"] = {{"integrator", "semi_implicit_euler"}, {"dt", 0.004}};
  } else {
    doc["ground"] = {{"type", "plane"}};
    doc["preset"] = "fast";
  }
  nlohmann::json cars = nlohmann::json::array();
  // 40 m apart on a 6 x 6 grid: no pair touches within the 5 s the
  // benchmark lets them drive before it starts over
  for (int i = 0; i < count; ++i) {
    const double x = -100.0 + 40.0 * (i % 6), y = -100.0 + 40.0 * (i / 6);
    nlohmann::json v = {{"name", "car" + std::to_string(i)}, {"initial", {{"position", {x, y, 0}}, {"speed", 2.0}}}};
    if (road_cars) {
      v["kind"] = "road_car";
      v["controls"] = {{{"t", 0.0}, {"throttle", 0.05}}};
    }
    cars.push_back(v);
  }
  doc["vehicles"] = cars;
  return scenario::buildScene(scenario::parseScenario(doc, scenario::FileAccess::local(GROUNDSIM_CONFIGS)));
}

scenario::Scene lanes(bool collisions) {
  nlohmann::json doc = scenario::loadScenarioDocument(std::string(GROUNDSIM_CONFIGS) + "/hills.json");
  doc.erase("vehicle");
  doc["name"] = "lanes";
  doc["duration"] = 1e4;
  doc["ground"] = {{"type", "plane"}};
  doc["collisions"] = {{"enabled", collisions}};
  doc["physics"] = {{"integrator", "semi_implicit_euler"}, {"dt", 0.004}};
  nlohmann::json cars = nlohmann::json::array();
  for (int i = 0; i < 8; ++i) {
    const double x = 12.0 * (i / 2), y = i % 2 ? 2.1 : -2.1;
    cars.push_back({{"name", "car" + std::to_string(i)},
                    {"kind", "road_car"},
                    {"initial", {{"position", {x, y, 0}}, {"speed", 15.0}}},
                    {"controls", {{{"t", 0.0}, {"throttle", 0.1}}}}});
  }
  doc["vehicles"] = cars;
  return scenario::buildScene(scenario::parseScenario(doc, scenario::FileAccess::local(GROUNDSIM_CONFIGS)));
}

void run(benchmark::State& st, const scenario::Scene& scene) {
  Simulator sim(scene.built.model, scene.built.initial);
  for (auto _ : st) {
    if (sim.state().t > 5.0) sim.restore(scene.built.initial);  // stay spread out
    scenario::stepScene(scene, sim, 100);
  }
  st.counters["steps/s"] = benchmark::Counter(100.0 * st.iterations(), benchmark::Counter::kIsRate);
  st.counters["specialised"] = sim.specialised() ? 1 : 0;
  st.counters["collisions"] = sim.model().collisions ? 1 : 0;
  st.counters["hits"] = static_cast<double>(sim.hits().size() + sim.takeEndedHits().size());
}

void Fleet(benchmark::State& st, bool road_cars, bool collisions) { run(st, fleet(road_cars, collisions)); }
void Lanes(benchmark::State& st, bool collisions) { run(st, lanes(collisions)); }

BENCHMARK_CAPTURE(Fleet, road_cars_hills_off, true, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Fleet, road_cars_hills_on, true, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Fleet, report_cars_fast_off, false, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Fleet, report_cars_fast_on, false, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Lanes, sedans_two_lanes_off, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Lanes, sedans_two_lanes_on, true)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace groundsim

BENCHMARK_MAIN();
