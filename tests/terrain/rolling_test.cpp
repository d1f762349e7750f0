// A heightfield sampled from an analytic ground gives that ground's rolling
// results: the lone hoop down an incline at g sin(theta) / 2, and the
// report's car in the cosine valley along the analytic run, closer as the
// cells shrink (at the spline's order).
#include <gtest/gtest.h>

#include <vector>

#include "grids.hpp"
#include "physics/build/model_builder.hpp"
#include "physics/simulator.hpp"
#include "physics/checks/telemetry.hpp"
#include "physics/build/vehicle.hpp"
#include "support/fit.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

using support::fittedAcceleration;

double hoopAcceleration(GroundPtr ground) {
  Options o;
  o.dt = 1e-4;
  o.contact.friction = 0.9;
  o.contact.damping = 60.0;
  ModelBuilder b(o, std::move(ground));
  CarParams p;
  p.wheel_contact = WheelContact::Circle;
  p.wheel_radius = 0.4;
  p.wheel_mass = 2.0;
  addLoneWheel(b, "hoop", p, CarPlacement{});
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  const double a = fittedAcceleration(sim, 0.5, 2.0);
  EXPECT_TRUE(sim.healthy());
  EXPECT_LT(sampleVehicle(sim, 0, false).wheels[0].slip, 1e-6);  // rolling, not sliding
  return a;
}

// x of the report's car body every 10 ms over `seconds` in the cosine valley.
std::vector<double> cosineRun(GroundPtr ground, double seconds) {
  Options o;
  o.contact.friction = 0.5;
  o.contact.damping = 20.0;
  CarPlacement at;
  at.position = Vec3(kPi, 0, 0);
  at.wheel_spin = 5.0;
  ModelBuilder b(o, std::move(ground));
  addCar(b, "car", CarParams{}, at);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  std::vector<double> xs;
  const long long every = std::llround(0.01 / o.dt);
  while (sim.state().t < seconds - 1e-12) {
    EXPECT_TRUE(sim.step(every));
    xs.push_back(bodyPos(sim.state().y, 0).x());
  }
  return xs;
}

double largestGap(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0;
  for (size_t k = 0; k < a.size(); ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

}  // namespace

TEST(HeightfieldRolling, LoneHoopRollsDownAHeightfieldInclineAtHalfGSinTheta) {
  const double theta = 25 * kPi / 180, slope = std::tan(theta);
  auto hf = sampledGround([&](double x, double) { return -slope * x; }, -10, 20, -3, 3, 0.1);
  const double a = hoopAcceleration(hf);
  const double expected = 9.8 * std::sin(theta) / 2;
  EXPECT_NEAR(a, expected, 1e-3 * expected);
  // the same as the analytic incline's run to well within that
  EXPECT_NEAR(a, hoopAcceleration(makeIncline(theta, Vec3::UnitX())), 1e-4 * expected);
}

TEST(HeightfieldRolling, ReportCarOnASampledCosineFollowsTheAnalyticRun) {
  // z = 0.5 cos x sampled with cells of 0.2 m and 0.1 m. The contact force
  // points along the normal, whose error is the spline's slope error,
  // O(cell^3) (ConvergesToTheSampledSurfaceAtFourthOrder: ~1e-4 and ~1.4e-5
  // here; heights are closer still, O(cell^4)), so the car's path differs
  // from the analytic ground's by the run's sensitivity times that, and the
  // gap shrinks ~8x per halving of the cells
  auto cosine = [](double x, double) { return 0.5 * std::cos(x); };
  const double T = 4.0;
  const auto exact = cosineRun(makeCosineWave(0.5, 2 * kPi), T);
  const auto coarse = cosineRun(sampledGround(cosine, -2, 12, -4, 4, 0.2), T);
  const auto fine = cosineRun(sampledGround(cosine, -2, 12, -4, 4, 0.1), T);
  double travel = 0;
  for (double x : exact) travel = std::max(travel, std::abs(x - kPi));
  EXPECT_GT(travel, 0.5);  // the car did move along the valley
  const double d_coarse = largestGap(coarse, exact), d_fine = largestGap(fine, exact);
  EXPECT_LT(d_fine, 1e-3) << "coarse " << d_coarse;
  EXPECT_GT(d_coarse / d_fine, 6.0) << d_coarse << " " << d_fine;  // order > 2.5
}
