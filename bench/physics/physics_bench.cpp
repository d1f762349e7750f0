// Steps per second of the physics core, one core, no I/O.
//   physics_bench                       all cases
//   physics_bench --benchmark_filter=Config/plain
// Counters: steps/s, and simulated seconds per wall second (sim_s_per_s).
#include <benchmark/benchmark.h>

#include <string>

#include "physics/kernels/batch_step.hpp"
#include "physics/simulator.hpp"
#include "physics/build/vehicle.hpp"
#include "scenario/presets.hpp"
#include "scenario/scenario.hpp"

using namespace groundsim;

namespace {

void report(benchmark::State& st, double dt) {
  st.counters["steps/s"] = benchmark::Counter(static_cast<double>(st.iterations()), benchmark::Counter::kIsRate);
  st.counters["sim_s_per_s"] =
      benchmark::Counter(static_cast<double>(st.iterations()) * dt, benchmark::Counter::kIsRate);
}

// The report's car on flat ground, wheels spun to 5 rad/s, dt 5e-5, with
// rim_points per wheel (the target: >= 1e6 steps/s at 20).
// ReportCarDeterministic: the same with physics.deterministic (the generic
// SSE2 build of the hot loops on every CPU): its cost.
void reportCar(benchmark::State& st, bool deterministic) {
  Options o;
  o.dt = 5e-5;
  o.deterministic = deterministic;
  CarParams p;
  p.rim_points = static_cast<int>(st.range(0));
  CarPlacement at;
  at.wheel_spin = 5.0;
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  addCar(b, "car", p, at);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  sim.step(2000);  // rolling, not the first touch
  double sweeps = 0;
  for (auto _ : st) {
    if (!sim.step()) st.SkipWithError("diverged");
    sweeps += sim.frictionSweeps();
  }
  report(st, o.dt);
  // mean Gauss-Seidel sweeps of the friction solve: its share of the cost
  st.counters["sweeps"] = sweeps / static_cast<double>(std::max<benchmark::IterationCount>(st.iterations(), 1));
}
void ReportCar(benchmark::State& st) { reportCar(st, false); }
void ReportCarDeterministic(benchmark::State& st) { reportCar(st, true); }
BENCHMARK(ReportCar)->Arg(20)->Arg(40)->Arg(80)->Arg(160);
BENCHMARK(ReportCarDeterministic)->Arg(20)->Arg(80);

// Continuous wheels (exact circle contact, bearing coupling), dt 1e-3.
void continuousWheelCar(benchmark::State& st, bool deterministic) {
  Options o;
  o.dt = 1e-3;
  o.deterministic = deterministic;
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.coupling = WheelCoupling::Bearing;
  CarPlacement at;
  at.wheel_spin = 5.0;
  ModelBuilder b(o, makePlane(Vec3::UnitZ(), 0));
  addCar(b, "car", p, at);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  sim.step(100);
  for (auto _ : st) {
    if (!sim.step()) st.SkipWithError("diverged");
  }
  report(st, o.dt);
}
void ContinuousWheelCar(benchmark::State& st) { continuousWheelCar(st, false); }
void ContinuousWheelCarDeterministic(benchmark::State& st) { continuousWheelCar(st, true); }
BENCHMARK(ContinuousWheelCar);
BENCHMARK(ContinuousWheelCarDeterministic);

// Each shipped scenario as written (its own ground, dt and vehicle).
void Config(benchmark::State& st, const std::string& name) {
  const auto sc = scenario::loadScenarioFile(std::string(GROUNDSIM_SOURCE_DIR) + "/configs/" + name + ".json");
  const auto scene = scenario::buildScene(sc);
  Simulator sim(scene.built.model, scene.built.initial);
  const long long steps = static_cast<long long>(scene.duration / sim.model().opt.dt);
  for (auto _ : st) {
    if (sim.state().tick >= steps) {  // start over rather than leave the scene
      st.PauseTiming();
      sim.restore(scene.built.initial);
      st.ResumeTiming();
    }
    if (!sim.step()) st.SkipWithError("diverged");
  }
  report(st, sim.model().opt.dt);
}

// A shipped scenario with a preset applied, as `groundsim run FILE --preset P`.
scenario::Scene presetScene(const std::string& name, const std::string& preset) {
  nlohmann::json doc =
      scenario::loadScenarioDocument(std::string(GROUNDSIM_SOURCE_DIR) + "/configs/" + name + ".json");
  doc["preset"] = preset;
  scenario::applyPreset(doc, /*force=*/true);
  return scenario::buildScene(scenario::parseScenario(doc, scenario::FileAccess::none()));
}

// The fast preset's car (five bodies, four circle contacts) on S1 and S2,
// one car in its Simulator (the specialised step, fast_car.hpp).
void FastPreset(benchmark::State& st, const std::string& name) {
  const auto scene = presetScene(name, "fast");
  Simulator sim(scene.built.model, scene.built.initial);
  const long long steps = static_cast<long long>(scene.duration / sim.model().opt.dt);
  for (auto _ : st) {
    if (sim.state().tick >= steps) {
      st.PauseTiming();
      sim.restore(scene.built.initial);
      st.ResumeTiming();
    }
    if (!sim.step()) st.SkipWithError("diverged");
  }
  report(st, sim.model().opt.dt);
  st.counters["specialised"] = sim.specialised() ? 1 : 0;
}

// range(0) fast-preset cars of S1 in one BatchStep, 16 steps per call;
// car-steps/s is the figure (the goal: 4M for 256 cars on one core).
void BatchFastPreset(benchmark::State& st) {
  const auto scene = presetScene("plain", "fast");
  const auto model = scene.built.model;
  BatchStep batch(model);
  std::vector<State> cars(static_cast<size_t>(st.range(0)), scene.built.initial);
  for (size_t i = 0; i < cars.size(); ++i) {  // a spread of drive torques: the lanes differ
    cars[i].controls.resize(model->wheels.size());
    for (auto& c : cars[i].controls) c.drive_torque = 0.002 * static_cast<double>(i % 7);
  }
  constexpr int kSteps = 16;
  for (auto _ : st) {
    if (cars.front().t > 20.0) {
      st.PauseTiming();
      for (auto& c : cars) {
        const auto controls = c.controls;
        c = scene.built.initial;
        c.controls = controls;
      }
      st.ResumeTiming();
    }
    batch.step(cars, kSteps);
  }
  const double car_steps = static_cast<double>(st.iterations()) * kSteps * static_cast<double>(cars.size());
  st.counters["car_steps/s"] = benchmark::Counter(car_steps, benchmark::Counter::kIsRate);
  st.counters["sim_s_per_s"] = benchmark::Counter(car_steps * model->opt.dt, benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(FastPreset, S1, std::string("plain"));
BENCHMARK_CAPTURE(FastPreset, S2, std::string("downhill"));
BENCHMARK(BatchFastPreset)->Arg(4)->Arg(64)->Arg(256)->Arg(1024);
BENCHMARK_CAPTURE(Config, sedan, std::string("sedan"));
BENCHMARK_CAPTURE(Config, plain, std::string("plain"));
BENCHMARK_CAPTURE(Config, downhill, std::string("downhill"));
BENCHMARK_CAPTURE(Config, uphill, std::string("uphill"));
BENCHMARK_CAPTURE(Config, cosine, std::string("cosine"));
BENCHMARK_CAPTURE(Config, cone, std::string("cone"));
BENCHMARK_CAPTURE(Config, parabola, std::string("parabola"));
BENCHMARK_CAPTURE(Config, bumps, std::string("bumps"));
BENCHMARK_CAPTURE(Config, expression, std::string("expression"));

BENCHMARK_MAIN();
