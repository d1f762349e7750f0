// The classical driver (server/drivers/classical_driver.*) on the shipped
// races, stepped in process with the race layer timing it: it completes
// the circuit's three laps and the rally stage without leaving the track,
// close to its line, and its flying laps are within a few percent of its
// own speed profile's quasi-steady-state lap (a car that holds the
// profile's speed everywhere would take exactly that long).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "drivers/lap_run.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::drivers {
namespace {

LapRun run(const std::string& file) {
  const scenario::Scenario s = scenario::loadScenarioFile(std::string(GROUNDSIM_CONFIGS) + "/" + file);
  const scenario::Scene scene = scenario::buildScene(s);
  return runClassical(s, scene, LapSetup{});
}

TEST(ClassicalDriver, LapsTheCircuitOnTheTrackNearItsProfile) {
  const LapRun r = run("race/circuit.json");
  ASSERT_TRUE(r.healthy) << r.why;
  std::printf("circuit: laps");
  for (double l : r.laps) std::printf(" %.2f", l);
  std::printf(" s, race %.2f s, profile's lap %.2f s, farthest %.2f m from the line\n", r.race_time, r.profile_lap,
              r.worst_offset);
  ASSERT_EQ(r.laps.size(), 3u);
  EXPECT_GT(r.race_time, 0.0) << "did not finish";
  EXPECT_EQ(r.off_track, 0);
  EXPECT_LT(r.worst_offset, 3.0);  // the track is 9 m either side of its centre line
  // flying laps (the first starts from the grid): slower than the profile
  // by the pedals' lag and the line's corners, never by more than 10%
  for (size_t k = 1; k < r.laps.size(); ++k) {
    EXPECT_GT(r.laps[k], 0.97 * r.profile_lap);
    EXPECT_LT(r.laps[k], 1.10 * r.profile_lap);
  }
}

TEST(ClassicalDriver, DrivesTheRallyStageOverEverySurface) {
  const LapRun r = run("race/rally_stage.json");
  ASSERT_TRUE(r.healthy) << r.why;
  std::printf("rally stage: %.2f s from the start line, race %.2f s, profile's flying run %.2f s, farthest %.2f m\n",
              r.laps.empty() ? 0.0 : r.laps[0], r.race_time, r.profile_lap, r.worst_offset);
  ASSERT_EQ(r.laps.size(), 1u);
  EXPECT_GT(r.race_time, 0.0) << "did not finish";
  EXPECT_EQ(r.off_track, 0);
  EXPECT_LT(r.worst_offset, 4.0);  // gates 12 m wide
  // from a standing start at the line: slower than the flying profile, by
  // at most the time a 0-to-speed launch costs (well under 20%)
  EXPECT_GT(r.laps[0], r.profile_lap);
  EXPECT_LT(r.laps[0], 1.20 * r.profile_lap);
}

}  // namespace
}  // namespace groundsim::drivers
