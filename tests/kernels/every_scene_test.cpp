// Every shipped scene that takes a specialised step path (FastCar,
// RingCar), at every preset, against the general loop it stands for: the
// same states up to round-off over the first second (structure review,
// section 1: one rigid-body physics, the general loop the reference).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

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
  long long steps = 0;
};

// Steps the scene on its specialised path and on the general loop side by
// side (Simulator::step's general branch: controls, then substeps of the
// integrator).
Compared compare(const scenario::Scene& scene, const std::string& what) {
  Simulator sim(scene.built.model, scene.built.initial);
  const Model& m = sim.model();
  State g = scene.built.initial;
  g.controls.resize(m.wheels.size());
  g.applied.resize(m.wheels.size());
  g.car_controls.resize(m.road_cars.size());
  g.cars.resize(m.road_cars.size());
  Workspace ws(m);
  auto integrator = makeIntegrator(m.opt.integrator);
  Compared c;
  c.what = what + (sim.ringCar() ? " (ring car)" : " (fast car)");
  const int n = std::max(1, m.opt.substeps);
  c.steps = std::min<long long>(std::llround(std::min(1.0, scene.duration) / m.opt.dt), 20000);
  for (long long k = 0; k < c.steps; ++k) {
    if (!sim.step()) break;
    applyControls(m, m.opt.dt, g);
    for (int s = 0; s < n; ++s) integrator->advance(m, g, ws, m.opt.dt / n);
    c.worst = std::max(c.worst, (sim.state().y - g.y).lpNorm<Eigen::Infinity>());
    c.scale = std::max(c.scale, g.y.lpNorm<Eigen::Infinity>());
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
      EXPECT_LT(c.worst, 1e-9 * (1.0 + c.scale)) << c.what << " after " << c.steps << " steps";
      std::printf("%-40s %6lld steps, largest difference %.3g (state scale %.3g)\n", c.what.c_str(), c.steps,
                  c.worst, c.scale);
    }
  }
  EXPECT_GE(compared, 4) << "too few shipped scenes take a specialised path: the test would mean little";
}

}  // namespace
}  // namespace groundsim
