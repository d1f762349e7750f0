// Every shipped scene that takes a specialised step path (FastCar,
// RingCar), at every preset, against the general loop it stands for: the
// same states up to round-off over the first second (structure review,
// section 1: one rigid-body physics, the general loop the reference).
// Both sides are judged healthy by the same check every step: a path that
// diverges where the other does not fails; a scene that diverges on both
// must do so at the same step, for the same reason, with the same states
// until then (issue 35: the comparison used to stop, passing, as soon as
// the fast path turned unhealthy).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "physics/checks/diagnostics.hpp"
#include "physics/integrators/integrator.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

namespace groundsim {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> shippedScenes() {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(GROUNDSIM_CONFIGS))
    if (e.is_regular_file() && e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

struct Compared {
  std::string what;
  double worst = 0.0;  // largest |y_fast - y_general| over the run
  double scale = 0.0;  // largest |y|
  long long steps = 0;  // to compare
  long long compared = 0;  // compared: steps, or the step both diverged at
  Health fast = Health::Ok, general = Health::Ok;  // at the end
  long long fast_failed = -1, general_failed = -1;  // the step each diverged at, or -1
  std::string fast_why, general_why;
};

// Steps the scene on its specialised path and on the general loop side by
// side (Simulator::step's general branch: controls, then substeps of the
// integrator).
Compared compare(const scenario::Scene& scene, const std::string& what) {
  Simulator sim(scene.built.model, scene.built.initial);
  const Model& m = sim.model();
  State g = sim.state();  // sized controls and the initial energy the health check needs
  Workspace ws(m);
  auto integrator = makeIntegrator(m.opt.integrator);
  Compared c;
  c.what = what + (sim.ringCar() ? " (ring car)" : " (fast car)");
  const int n = std::max(1, m.opt.substeps);
  c.steps = std::min<long long>(std::llround(std::min(1.0, scene.duration) / m.opt.dt), 20000);
  for (long long k = 0; k < c.steps; ++k) {
    const bool fast_ok = sim.step();
    applyControls(m, m.opt.dt, g);
    for (int s = 0; s < n; ++s) integrator->advance(m, g, ws, m.opt.dt / n);
    ++g.tick;
    g.t = static_cast<double>(g.tick) * m.opt.dt;
    // Simulator::step's check, with its energy check every kEnergyCheckInterval steps
    const bool general_ok = checkHealth(m, g, ws, g.tick % Simulator::kEnergyCheckInterval == 0);
    if (!fast_ok) {
      c.fast = sim.state().health;
      c.fast_failed = k;
      c.fast_why = sim.state().health_reason;
    }
    if (!general_ok) {
      c.general = g.health;
      c.general_failed = k;
      c.general_why = g.health_reason;
    }
    if (!fast_ok || !general_ok) break;  // judged by the caller: both at this step, or a failure
    c.worst = std::max(c.worst, (sim.state().y - g.y).lpNorm<Eigen::Infinity>());
    c.scale = std::max(c.scale, g.y.lpNorm<Eigen::Infinity>());
    c.compared = k + 1;
  }
  return c;
}

TEST(Kernels, EveryShippedSceneOnAFastPathIsTheGeneralLoopUpToRoundOff) {
  int compared = 0;
  for (const fs::path& path : shippedScenes()) {
    for (const char* preset : {"", "fast", "balanced", "accurate"}) {
      nlohmann::json doc = scenario::loadScenarioDocument(path.string());
      if (*preset) doc["preset"] = preset;
      scenario::Scene scene;
      try {
        scene = scenario::buildScene(
            scenario::parseScenario(doc, scenario::FileAccess::local(path.parent_path().string())));
      } catch (const scenario::ScenarioError&) {
        continue;  // a preset that does not fit this scene (e.g. a road car's keys)
      }
      Simulator probe(scene.built.model, scene.built.initial);
      if (!probe.specialised() && !probe.ringCar()) continue;
      const Compared c = compare(scene, path.filename().string() + (*preset ? std::string(" preset ") + preset : ""));
      ++compared;
      // sums in another order round differently; states are O(1..100) here
      EXPECT_LT(c.worst, 1e-9 * (1.0 + c.scale)) << c.what << " over " << c.compared << " steps";
      // to the end, or diverged on both paths at the same step for the same reason
      EXPECT_EQ(c.fast_failed, c.general_failed)
          << c.what << ": the fast path diverged at step " << c.fast_failed << " (" << c.fast_why
          << "), the general loop at step " << c.general_failed << " (" << c.general_why << "; -1: never)";
      EXPECT_EQ(c.fast, c.general) << c.what << ": " << c.fast_why << " / " << c.general_why;
      if (c.fast_failed < 0 && c.general_failed < 0) {
        EXPECT_EQ(c.compared, c.steps) << c.what;
      }
      std::printf("%-40s %6lld of %6lld steps, largest difference %.3g (state scale %.3g)%s%s\n", c.what.c_str(),
                  c.compared, c.steps, c.worst, c.scale, c.fast_failed >= 0 ? ", diverged: " : "",
                  c.fast_failed >= 0 ? c.fast_why.c_str() : "");
    }
  }
  EXPECT_GE(compared, 4) << "too few shipped scenes take a specialised path: the test would mean little";
}

}  // namespace
}  // namespace groundsim
