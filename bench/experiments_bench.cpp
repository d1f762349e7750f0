// Throughput of the in-process vectorised environments (issue 11's target:
// 250,000 env-steps/s on one core for 256 fast-preset cars at 8 physics
// steps per action, 1.8x that on 2 threads).
//   experiments_bench                                  1 and 2 threads
//   experiments_bench --benchmark_filter=FastCar/1
// One iteration is one batched step of all environments (autoresets, with
// their drawn placements, included). Counters: env_steps/s and
// physics_steps/s (wall clock), and env_steps/cpu_s: per second of CPU
// time of the whole process (all threads), the figure a loaded machine
// still measures fairly: a thread's share of a shared core does not count.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <ctime>
#include <vector>

#include "experiments/vec_env.hpp"

using namespace groundsim::experiments;

namespace {

void FastCar(benchmark::State& st) {
  const int n = 256, threads = static_cast<int>(st.range(0));
  auto env = makeVecEnvFromFile(std::string(GROUNDSIM_SOURCE_DIR) + "/configs/tasks/fast_car.json", n,
                                {.num_threads = threads});
  const Layout& l = env->layout();
  std::vector<float> obs(static_cast<size_t>(n * l.obsSize())), act(static_cast<size_t>(n * l.actionSize()));
  std::vector<double> rew(n);
  std::vector<std::uint8_t> term(n), trunc(n);
  for (size_t i = 0; i < act.size(); ++i) act[i] = (i % 3 == 0) ? 1.0f : 0.6f;
  env->reset(0, obs.data());
  for (int i = 0; i < 50; ++i) env->step(act.data(), obs.data(), rew.data(), term.data(), trunc.data());
  auto cpu = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  const double cpu0 = cpu();
  for (auto _ : st) {
    env->step(act.data(), obs.data(), rew.data(), term.data(), trunc.data());
    benchmark::DoNotOptimize(obs.data());
  }
  const double cpu_s = cpu() - cpu0;
  const double steps = static_cast<double>(st.iterations()) * n;
  st.counters["env_steps/cpu_s"] = steps / cpu_s;
  st.counters["env_steps/s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
  st.counters["physics_steps/s"] = benchmark::Counter(steps * l.control_period, benchmark::Counter::kIsRate);
}
BENCHMARK(FastCar)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
