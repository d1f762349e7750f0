// Stability before accuracy (docs/accuracy.md, "How the choice is made",
// step 2): for every shipped scene and tolerances of 10%, 1% and 0.1%, the
// setting the chooser takes draws no warning from the stability check of
// the scene it runs (physics/checks/stability.cpp: a step at or beyond
// kStabilityMargin of a mode's limit), whichever model and integrator it
// took. The scenes are cut to their first second: the stiff modes are the
// model's, not the path's, and the pilot then stays short.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "physics/checks/stability.hpp"
#include "physics/integrators/integrator.hpp"
#include "scenes.hpp"

namespace groundsim::accuracy {
namespace {

std::vector<std::string> shippedScenes() {
  const std::filesystem::path root(GROUNDSIM_CONFIGS);
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
    if (!e.is_regular_file() || e.path().extension() != ".json") continue;
    const std::string rel = std::filesystem::relative(e.path(), root).generic_string();
    if (rel.rfind("tasks/", 0) == 0) continue;  // tasks, not scenarios (they name one)
    out.push_back(rel);
  }
  std::sort(out.begin(), out.end());
  return out;
}

class StableChoice : public ::testing::TestWithParam<std::string> {};

TEST_P(StableChoice, NoChosenSettingDrawsAStabilityWarning) {
  const scenario::Scenario s = test::config(GetParam(), {"duration=1"});
  for (double tol : {0.1, 0.01, 0.001}) {
    const Choice c = chooseSettings(s, tol);
    SCOPED_TRACE(c.line() + "\n" + c.report());
    const scenario::Scene chosen = scenario::buildScene(c.scenario);
    const std::vector<std::string> warnings = stabilityWarnings(*chosen.built.model);
    for (const std::string& w : warnings) ADD_FAILURE() << "tolerance " << tol << ": " << w;
    for (const IntegratorTrial& t : c.trials)
      if (t.usable) EXPECT_LT(t.dt0, kStabilityMargin * t.stability_dt) << integratorName(t.kind);
  }
}

INSTANTIATE_TEST_SUITE_P(Shipped, StableChoice, ::testing::ValuesIn(shippedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                           std::string n = i.param.substr(0, i.param.size() - 5);
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace groundsim::accuracy
