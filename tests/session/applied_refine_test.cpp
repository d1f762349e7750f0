// The applied log's refinement entry (KIND_REFINE, docs/accuracy.md,
// Refinement): applied again by a re-simulation or a standby, it doubles
// the substeps at its tick; an entry that does not (a forged or corrupted
// one) is refused naming why, and the simulation is left as it was.
#include <gtest/gtest.h>

#include "fakes.hpp"
#include "stepping/applied.hpp"

namespace groundsim::session::test {
namespace {

TEST(AppliedRefine, DoublesTheSubstepsAndRefusesAnythingElse) {
  const scenario::Scene scene = carScene(1e-4);
  Simulator sim(scene.built.model, scene.built.initial);
  DrivenCars cars;
  const std::vector<VehicleWheels> vehicles = vehicleWheels(sim.model());
  Applied a;
  a.kind = AppliedKind::Refine;
  a.steps = 2;
  EXPECT_EQ(applyEntry(sim, cars, vehicles, scene.built.initial, a), "");
  EXPECT_EQ(sim.model().opt.substeps, 2);
  for (const std::int64_t bad : {std::int64_t{2}, std::int64_t{8}, std::int64_t{0}, std::int64_t{-4},
                                 std::int64_t{1} << 40}) {
    a.steps = bad;
    const std::string why = applyEntry(sim, cars, vehicles, scene.built.initial, a);
    EXPECT_NE(why.find("a refinement doubles them"), std::string::npos) << bad << ": " << why;
    EXPECT_EQ(sim.model().opt.substeps, 2) << bad;
  }
  a.steps = 4;
  EXPECT_EQ(applyEntry(sim, cars, vehicles, scene.built.initial, a), "");
  EXPECT_EQ(sim.model().opt.substeps, 4);
  EXPECT_TRUE(sim.step(10));
  EXPECT_EQ(sim.state().tick, 10);
}

}  // namespace
}  // namespace groundsim::session::test
