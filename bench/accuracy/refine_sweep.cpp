// `refine_sweep`: what refinement at a safe point buys (docs/accuracy.md,
// "Refinement at a safe point"). For each scene and tolerance T, a run
// starts at a setting meant for a looser tolerance (the chooser's choice at
// 10 T, its live estimate carrying that pilot's prediction, as a session
// piloted for 10 T and watched for T would) and refines when the estimate
// says the setting errs by more than T. Printed per run: the error of the start
// setting left alone, the refined run's substeps, error and force
// evaluations, and the chooser's own choice at T for comparison, all
// against a converged reference (velocity Verlet at 0.02 s / 64, its
// uncertainty the difference to 0.02 s / 32; a row is judged only where
// that is below T / 3).
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "accuracy/error_measure.hpp"
#include "accuracy/pilot.hpp"
#include "accuracy/refinement.hpp"
#include "accuracy/trajectory.hpp"
#include "scenario/scenario.hpp"
#include "tolerance_scenes.hpp"

namespace groundsim::bench {
namespace {

accuracy::Trajectory reference(const scenario::Scenario& s, double dt) {
  // contact refined with the step: the floor contact needs at 64 dt
  return accuracy::runTrajectory(accuracy::withSettings(s, IntegratorKind::VelocityVerlet, dt, 1), s.duration);
}

double evalsPerSecond(const accuracy::Trajectory& t) {
  return static_cast<double>(t.evaluations) / std::max(t.duration, 1e-9);
}

}  // namespace
}  // namespace groundsim::bench

int main(int argc, char** argv) {
  using namespace groundsim;
  using namespace groundsim::bench;
  CLI::App app{"Refinement at a safe point: a coarse start refined to the tolerance, against the converged reference"};
  std::vector<std::string> only{"sedan_launch_brake", "sedan_slalom",   "sedan_skidpad",
                                "sedan_stick_slip",   "sedan_wet",      "sedan_hills_heightfield",
                                "lone_wheel_kerb",    "slalom_long",    "wet_long"};
  std::vector<double> tolerances{0.01, 0.001};
  std::string configs = GROUNDSIM_CONFIGS;
  app.add_option("--scenes", only, "Scene names of tolerance_scenes.cpp")->delimiter(',');
  app.add_option("--tolerances", tolerances, "Tolerances")->delimiter(',');
  app.add_option("--configs", configs, "The configs directory");
  CLI11_PARSE(app, argc, argv);

  std::printf("| scene | T | start (chooser at 10 T) | alone: error | refined to (substeps) | refined: error | within T |"
              " evals / alone | chooser at T: setting, error | its evals / alone |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  int judged = 0, within = 0, needed = 0, rescued = 0;
  for (const ToleranceScene& sc : toleranceScenes()) {
    if (std::find(only.begin(), only.end(), sc.name) == only.end()) continue;
    const scenario::Scenario base = loadToleranceScene(configs, sc);
    const accuracy::Trajectory ref = reference(base, 0.02 / 64);
    const double uncertainty = accuracy::compareRuns(reference(base, 0.02 / 32), ref).value();
    for (const double T : tolerances) {
      if (uncertainty > T / 3) {
        std::printf("| %s | %g | not judged: reference known to %.1e | | | | | | | |\n", sc.name.c_str(), T, uncertainty);
        continue;
      }
      const accuracy::Choice start = accuracy::chooseSettings(base, 10 * T);
      const accuracy::Choice at_t = accuracy::chooseSettings(base, T);
      const accuracy::Trajectory alone = accuracy::runTrajectory(start.scenario, base.duration);
      const accuracy::RefinedRun r = accuracy::runRefined(start.scenario, start.order, {T, true, 3},
                                                           start.prediction());
      const accuracy::Trajectory chosen = accuracy::runTrajectory(at_t.scenario, base.duration);
      const double e_alone = accuracy::compareRuns(alone, ref).value();
      const double e_refined = accuracy::compareRuns(r.run, ref).value();
      const double e_chosen = accuracy::compareRuns(chosen, ref).value();
      std::string subs;
      for (const auto& f : r.refinements) {
        char b[48];
        std::snprintf(b, sizeof b, "%s%d at %.2f s", subs.empty() ? "" : ", ", f.substeps,
                      static_cast<double>(f.tick) * start.scenario.options.dt);
        subs += b;
      }
      if (subs.empty()) subs = "none";
      ++judged;
      within += e_refined <= T;
      needed += e_alone > T;
      rescued += e_alone > T && e_refined <= T;
      std::printf("| %s | %g | %s %.3g | %.2e | %s | %.2e | %s | %.2f | %s %.3g, %.2e | %.2f |\n", sc.name.c_str(), T,
                  integratorName(start.integrator), start.dt, e_alone, subs.c_str(), e_refined,
                  e_refined <= T ? "yes" : "**no**", evalsPerSecond(r.run) / evalsPerSecond(alone),
                  integratorName(at_t.integrator), at_t.dt, e_chosen, evalsPerSecond(chosen) / evalsPerSecond(alone));
      std::fflush(stdout);
    }
  }
  std::printf("\nJudged %d: the start alone over T in %d; refined within T in %d; of those over T alone, within T "
              "after refinement %d.\n", judged, needed, within, rescued);
  return 0;
}
