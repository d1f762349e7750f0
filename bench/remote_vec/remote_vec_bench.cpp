// Per-step cost of a vectorised session over LCM (RemoteVecEnv) against the
// same batch stepped in process (makeVecEnv on one thread, as the server
// steps it), for several batch sizes. Prints the figures of
// docs/experiments.md; run.sh starts the server in a private network
// namespace.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "client/experiments/remote_vec_env.hpp"
#include "experiments/vec_env.hpp"
#include "support/actions.hpp"

using namespace groundsim::experiments;
using Clock = std::chrono::steady_clock;

namespace {


// Seconds per batched step: a few steps to warm up, then steps until
// min_seconds have passed (at least min_steps). Actions are made beforehand.
double perStep(BatchEnv& env, double min_seconds, int min_steps) {
  const Layout& l = env.layout();
  const int n = l.num_envs;
  std::vector<std::vector<float>> actions;
  for (int k = 0; k < 64; ++k) actions.push_back(groundsim::test::sweepActions(l, n, k));
  std::vector<float> obs(static_cast<std::size_t>(n) * l.obsSize());
  std::vector<double> rew(n);
  std::vector<std::uint8_t> te(n), tr(n);
  env.reset(1, obs.data());
  for (int k = 0; k < 3; ++k) env.step(actions[k].data(), obs.data(), rew.data(), te.data(), tr.data());
  const auto t0 = Clock::now();
  int steps = 0;
  double elapsed = 0;
  while (steps < min_steps || elapsed < min_seconds) {
    env.step(actions[steps % 64].data(), obs.data(), rew.data(), te.data(), tr.data());
    ++steps;
    elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  return elapsed / steps;
}

}  // namespace

int main(int argc, char** argv) {
  std::string url, scenario;
  std::vector<int> sizes{16, 256, 1024};
  double seconds = 1.0;
  int repeats = 3;
  CLI::App app{"remote_vec_bench: vectorised session over LCM vs in process"};
  app.add_option("scenario", scenario, "task scenario (e.g. configs/tasks/fast_car.json)")->required();
  app.add_option("--lcm-url", url, "the server's LCM URL");
  app.add_option("--sizes", sizes, "batch sizes")->delimiter(',');
  app.add_option("--seconds", seconds, "wall seconds per measurement");
  app.add_option("--repeats", repeats, "alternating measurements of each; the fastest of each counts");
  CLI11_PARSE(app, argc, argv);
  std::ifstream in(scenario);
  std::stringstream text;
  text << in.rdbuf();

  std::printf("%6s  %14s  %14s  %14s  %8s  %12s\n", "envs", "in-process ms", "remote ms", "overhead ms", "ratio",
              "remote env/s");
  for (int n : sizes) {
    VecEnvOptions opt;
    opt.num_threads = 1;  // the server steps a session on one worker
    opt.max_envs = n;
    // the machine is shared: alternate the two, keep the fastest of each
    // (the least disturbed), with both environments built once
    auto local_env = makeVecEnv(text.str(), n, opt);
    RemoteVecOptions ro;
    ro.lcm_url = url;
    RemoteVecEnv remote_env(text.str(), n, ro);
    double local = 1e30, remote = 1e30;
    for (int r = 0; r < repeats; ++r) {
      local = std::min(local, perStep(*local_env, seconds, 20));
      remote = std::min(remote, perStep(remote_env, seconds, 20));
    }
    std::printf("%6d  %14.3f  %14.3f  %14.3f  %8.3f  %12.0f\n", n, local * 1e3, remote * 1e3, (remote - local) * 1e3,
                remote / local, n / remote);
    std::fflush(stdout);
  }
  return 0;
}
