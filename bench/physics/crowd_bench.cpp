// Crowds (issue 33): what cars that touch, or may touch, cost against the
// same cars apart. Each scene of bench/physics/crowd/ (copies of
// configs/sedan.json's car at 10 m/s on a plane, 20 s at the scene's own
// step) is stepped from its start to its end, `rounds` times; the best
// round's CPU time gives steps/s. Prints the table of docs/performance.md
// ("Crowds") with each scene's cost against its reference (the pair apart,
// or the same number of cars spread), the substeps the run took per step
// and its hits.
// Run: build/bench/physics/crowd_bench [rounds (default 5)] [scene dir] [one scene, for a profile]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace {

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Row {
  const char* scene;
  const char* reference;  // the scene it is compared with
  const char* what;
};

struct Result {
  double steps_per_s = 0.0;
  double evaluations_per_step = 0.0;
  double contact_substeps_per_step = 0.0;
  size_t hits = 0;
};

Result measure(const std::string& path, int rounds) {
  const groundsim::scenario::Scene scene =
      groundsim::scenario::buildScene(groundsim::scenario::loadScenarioFile(path));
  const double dt = scene.built.model->opt.dt;
  const long long steps = std::llround(scene.duration / dt);
  Result r;
  double best = 1e300;
  for (int k = 0; k < rounds; ++k) {
    groundsim::Simulator sim(scene.built.model, scene.built.initial);
    const double t0 = cpuSeconds();
    const bool ok = groundsim::scenario::stepScene(scene, sim, steps);
    const double t = cpuSeconds() - t0;
    if (!ok) {
      std::fprintf(stderr, "%s: diverged at t = %.3f s: %s\n", path.c_str(), sim.state().t,
                   sim.state().health_reason.c_str());
      std::exit(1);
    }
    best = std::min(best, t);
    r.evaluations_per_step = static_cast<double>(sim.forceEvaluations()) / static_cast<double>(steps);
    r.contact_substeps_per_step = static_cast<double>(sim.contactSubstepCount()) / static_cast<double>(steps);
    r.hits = sim.hits().size() + sim.takeEndedHits().size();
  }
  r.steps_per_s = static_cast<double>(steps) / best;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const std::string dir = argc > 2 ? argv[2] : std::string(GROUNDSIM_SOURCE_DIR) + "/bench/physics/crowd";
  const std::vector<Row> rows = {
      {"pair_apart", "pair_apart", "2 sedans, centres 20 m apart"},
      {"pair_near", "pair_apart", "2 sedans side by side, centres 2.2 m apart (0.4 m gap)"},
      {"push", "pair_apart", "2 sedans, one pushing the other (sustained contact)"},
      {"spread8", "spread8", "8 sedans spread (10 m lanes, 15 m apart)"},
      {"pack8", "spread8", "8 sedans in a pack (2 abreast 2.3 m, 5.2 m nose to nose)"},
      {"spread16", "spread16", "16 sedans spread"},
      {"pack16", "spread16", "16 sedans in a pack"},
      {"spread16_push", "spread16", "14 sedans spread, a pair pushing in a third lane"},
  };
  std::vector<std::pair<std::string, Result>> done;
  std::printf(
      "| scene | steps/s | cost against | evaluations per step | contact substeps per step | hits |\n"
      "|---|---|---|---|---|---|\n");
  const std::string only = argc > 3 ? argv[3] : "";
  for (const Row& row : rows) {
    if (!only.empty() && only != row.scene) continue;
    const Result r = measure(dir + "/" + row.scene + ".json", rounds);
    done.emplace_back(row.scene, r);
    double ref = r.steps_per_s;
    for (const auto& [name, d] : done)
      if (name == row.reference) ref = d.steps_per_s;
    std::printf("| %s: %s | %.0f | %.2fx %s | %.2f | %.2f | %zu |\n", row.scene, row.what, r.steps_per_s,
                ref / r.steps_per_s, row.reference, r.evaluations_per_step, r.contact_substeps_per_step, r.hits);
    std::fflush(stdout);
  }
  return 0;
}
