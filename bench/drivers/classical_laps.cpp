// The classical driver's laps on a race scenario (docs/drivers.md): vehicle
// 0 driven by pure pursuit on the track's line with a speed profile from its
// curvature and the ground's friction, timed by the race layer. Prints each
// lap, the race time, the profile's own flying lap, times off track, the
// farthest it strayed from the line, and wall time.
// Run: build/bench/drivers/classical_laps SCENARIO [grip m/s^2 at mu 1 (default 9)]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "drivers/lap_run.hpp"
#include "scenario/scenario.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: classical_laps SCENARIO [grip]\n");
    return 2;
  }
  using namespace groundsim;
  const scenario::Scenario s = scenario::loadScenarioFile(argv[1]);
  const scenario::Scene scene = scenario::buildScene(s);
  drivers::LapSetup setup;
  if (argc > 2) setup.limits.grip = std::atof(argv[2]);
  const auto t0 = std::chrono::steady_clock::now();
  const drivers::LapRun r = drivers::runClassical(s, scene, setup);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: line %.0f m, profile's flying lap %.2f s (grip %.1f m/s^2 at mu 1)\n", argv[1], r.line_length,
              r.profile_lap, setup.limits.grip);
  for (size_t k = 0; k < r.laps.size(); ++k) std::printf("  lap %zu: %.2f s\n", k + 1, r.laps[k]);
  std::printf("  race time %.2f s%s, off track %d times, farthest from the line %.2f m, wall %.2f s%s%s\n",
              r.race_time, r.race_time > 0.0 ? "" : " (did not finish)", r.off_track, r.worst_offset, wall,
              r.healthy ? "" : ", diverged: ", r.why.c_str());
  return r.race_time > 0.0 && r.healthy ? 0 : 1;
}
