// libFuzzer target: scenario text -> pre-scan and validation against the
// budget -> scene building. Every input must end in a Scene or a
// ScenarioError; anything else (a crash, another exception, a sanitizer
// report, a leak) is a finding. The budget is the runner's default, lowered
// where a valid input could otherwise take long to build (many rim points),
// so the fuzzer keeps its speed; the limits themselves are what is tested.
// Seed corpus: fuzz/scenario_seeds.txt lists the files to copy in.
#include <cstddef>
#include <cstdint>
#include <string>

#include "scenario/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const groundsim::scenario::Budget budget = [] {
    groundsim::scenario::Budget b;
    b.max_document_bytes = 1 << 20;
    b.max_points = 20000;
    b.max_springs = 40000;
    b.max_particles = 10000;
    b.max_state = 100000;
    b.max_implicit_state = 500;
    return b;
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const groundsim::scenario::Scenario s = groundsim::scenario::parseScenario(text, budget);
    const groundsim::scenario::ModelSize size = groundsim::scenario::estimateModelSize(s);
    const groundsim::scenario::Scene scene = groundsim::scenario::buildScene(s);
    // the budget is only as good as the estimate: it must count what was built
    const groundsim::Model& m = *scene.built.model;
    if (size.points != static_cast<long long>(m.points.size()) ||
        size.springs != static_cast<long long>(m.springs.size()) ||
        size.particles != static_cast<long long>(m.particles.size()) || size.state != m.stateSize())
      __builtin_trap();
  } catch (const groundsim::scenario::ScenarioError& e) {
    // a refusal: its report must stay short whatever the input
    if (std::string(e.what()).size() > 40000) __builtin_trap();
  }
  return 0;
}
