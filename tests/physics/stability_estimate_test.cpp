// The load-time stability estimate predicts what runs do: the report's car
// is healthy a little below the estimated limit and diverges above it.
#include <gtest/gtest.h>

#include "physics/checks/stability.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

bool survives(double dt, double seconds) {
  Options o;
  o.dt = dt;
  CarPlacement at;
  at.wheel_spin = 5.0;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), {}, at);
  Simulator sim(built.model, built.initial);
  return sim.step(static_cast<long long>(seconds / dt));
}

}  // namespace

TEST(StabilityEstimate, RimSpringsOfTheReportCarSetTheLimit) {
  Options o;
  o.dt = 5e-5;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0));
  const auto modes = stiffestModes(*built.model);
  ASSERT_EQ(modes.size(), 3u);  // ground, all on one part, spring pairs
  const StiffMode& springs = modes[2];
  // 40 springs of 1e5 N/m between a 0.1 kg wheel and the 1 kg body
  EXPECT_NEAR(springs.omega, std::sqrt(40 * 1e5 * (1 / 0.1 + 1 / 1.0)), 1e-6 * springs.omega);
  EXPECT_TRUE(stabilityWarnings(*built.model).empty());  // dt 5e-5 is far below
  const double limit = springs.dt_limit;
  EXPECT_TRUE(survives(0.8 * limit, 2.0));
  EXPECT_FALSE(survives(1.5 * limit, 2.0));
}

TEST(StabilityEstimate, WarnsNamingTheSettingAndTheLimit) {
  Options o;
  o.dt = 1e-3;
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0));
  const auto w = stabilityWarnings(*built.model);
  ASSERT_FALSE(w.empty());
  EXPECT_NE(w[0].find("/physics/dt"), std::string::npos);
  EXPECT_NE(w[0].find("beyond the stability limit"), std::string::npos);
}

TEST(StabilityEstimate, WarnsWhenTheGroundCannotHoldTheVehicleUp) {
  Options o;
  o.dt = 5e-5;
  CarParams heavy;
  heavy.body_mass = 1500.0;  // sag 1500 g / (4 * 2000) ~ 1.8 m against a 0.5 m limit
  auto built = reportCar(o, makePlane(Vec3::UnitZ(), 0), heavy);
  bool sag_warning = false;
  for (const auto& w : stabilityWarnings(*built.model))
    sag_warning |= w.find("/contact/stiffness") != std::string::npos;
  EXPECT_TRUE(sag_warning);
  // and the warning is right: the run hits the penetration limit
  Simulator sim(built.model, built.initial);
  EXPECT_FALSE(sim.step(20000));
  EXPECT_EQ(sim.state().health, Health::Penetration);
}
