// libFuzzer target: scenario text -> parseScenario (validation) -> buildScene
// -> a few steps. A ScenarioError is the answer hostile text must get; any
// other exception, a crash, a sanitizer report, a leak, an allocation beyond
// -malloc_limit_mb or a run beyond -timeout is a finding (scripts/fuzz.sh).
// The steps check the core's promise: a validated scene never has
// undefined behaviour, it reports divergence as health.
#include <cstddef>
#include <cstdint>
#include <string>

#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace groundsim;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const scenario::Scenario sc = scenario::parseScenario(text);
    scenario::Scene scene = scenario::buildScene(sc);
    Simulator sim(scene.built.model, scene.built.initial);
    sim.step(8);
  } catch (const scenario::ScenarioError&) {
    // refused with its path: the expected answer
  }
  return 0;
}
