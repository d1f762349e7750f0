// The track line and the speed profile (server/drivers/track_line.*)
// against closed forms: a circle's length, curvature and offsets, the
// steady cornering speed sqrt(a R) and its lap 2 pi R / v, and braking
// v^2 = v_b^2 + 2 a d before a slower stretch.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "drivers/track_line.hpp"

namespace groundsim::drivers {
namespace {

constexpr double kPi = std::numbers::pi;

// A circle of radius r, counter-clockwise from (r, 0), as n points.
std::vector<Vec2> circle(double r, int n) {
  std::vector<Vec2> p;
  for (int k = 0; k < n; ++k) p.push_back({r * std::cos(2 * kPi * k / n), r * std::sin(2 * kPi * k / n)});
  return p;
}

TEST(TrackLine, ACircleHasItsLengthCurvatureAndOffsets) {
  const double r = 50.0;
  const int n = 400;
  const TrackLine line(circle(r, n), true, 1.0);
  // the polygon's perimeter: 2 n r sin(pi / n)
  EXPECT_NEAR(line.length(), 2.0 * n * r * std::sin(kPi / n), 1e-9);
  for (double s : {0.0, 37.0, 150.0, 300.5}) {
    // + : turning left. The resampled points lie on the polygon's chords,
    // up to r (1 - cos(pi / n)) = 1.5 mm inside the circle, against the
    // 8 m window's sagitta of w^2 / 2r = 0.64 m: within 3e-3
    EXPECT_NEAR(line.curvatureAt(s, 8.0), 1.0 / r, 3e-3 / r) << "at s = " << s;
    // a point 3 m outside the circle, at the line's angle s / r, is 3 m to its right
    const double a = s / r;
    const TrackLine::Where w = line.locate({(r + 3.0) * std::cos(a), (r + 3.0) * std::sin(a)});
    EXPECT_NEAR(w.s, s, 0.05) << "at s = " << s;
    EXPECT_NEAR(w.offset, -3.0, 0.01);
    // searched near a hint, the same
    EXPECT_NEAR(line.locate({(r - 2.0) * std::cos(a), (r - 2.0) * std::sin(a)}, s + 5.0, 20.0).offset, 2.0, 0.01);
  }
  // the tangent runs counter-clockwise
  const Vec2 t = line.tangentAt(0.0);
  EXPECT_NEAR(t[0], 0.0, 1e-2);
  EXPECT_NEAR(t[1], 1.0, 1e-3);
  // a circuit wraps, a stage clamps
  EXPECT_NEAR(line.wrap(line.length() + 10.0), 10.0, 1e-9);
  const TrackLine stage({{0.0, 0.0}, {100.0, 0.0}}, false, 1.0);
  EXPECT_DOUBLE_EQ(stage.wrap(130.0), 100.0);
  EXPECT_DOUBLE_EQ(stage.curvatureAt(50.0, 8.0), 0.0);
  EXPECT_THROW(TrackLine({{1.0, 1.0}}, true), std::invalid_argument);
  EXPECT_THROW(TrackLine({{1.0, 1.0}, {1.0, 1.0}}, false), std::invalid_argument);
}

// A hostile race: 10,000 centre-line points zigzagging across the
// scenario's 100 km (2e9 m of line) is resampled within kMaxSamples, not
// every metre.
TEST(TrackLine, ALineAcrossTheScenariosExtentStaysWithinItsSamples) {
  std::vector<Vec2> zigzag;
  for (int k = 0; k < 10000; ++k) zigzag.push_back({k % 2 ? 1e5 : -1e5, k % 2 ? -1e5 : 1e5});
  const TrackLine line(zigzag, true, 1.0);
  EXPECT_GT(line.length(), 2e9);
  EXPECT_LE(line.samples(), TrackLine::kMaxSamples);
  EXPECT_NEAR(line.spacing(), line.length() / line.samples(), 1e-6 * line.spacing());
}

TEST(SpeedProfile, SteadyCorneringOnACircle) {
  const double r = 40.0, grip = 8.0;
  const TrackLine line(circle(r, 360), true, 1.0);
  CarLimits car;
  car.grip = grip;
  car.top = 100.0;
  car.straight_radius = 1e9;
  const SpeedProfile p(line, car);
  const double v = std::sqrt(grip * r);
  for (double s : {0.0, 60.0, 200.0}) EXPECT_NEAR(p.at(s), v, 2e-3 * v);
  EXPECT_NEAR(p.lapTime(), line.length() / v, 2e-3 * line.length() / v);
  // friction 0.25 everywhere: half the speed
  const SpeedProfile slippery(line, car, std::vector<double>(line.samples(), 0.25));
  EXPECT_NEAR(slippery.at(30.0), 0.5 * v, 2e-3 * v);
}

TEST(SpeedProfile, BrakesBeforeASlowerSurfaceAsVSquaredIsTwoAD) {
  // 1 km straight; ice (mu 0.1) from 600 m: there at most sqrt(0.1 grip R)
  const TrackLine line({{0.0, 0.0}, {1000.0, 0.0}}, false, 1.0);
  const CarLimits car{9.0, 8.0, 3.0, 60.0, 250.0};  // grip, brake, accel, top, straight_radius
  std::vector<double> mu(line.samples(), 1.0);
  for (int i = 600; i < line.samples(); ++i) mu[i] = 0.1;
  const SpeedProfile p(line, car, mu);
  const double on_ice = std::sqrt(0.1 * 9.0 * 250.0), dry = std::sqrt(9.0 * 250.0);
  EXPECT_NEAR(p.at(800.0), on_ice, 1e-9);
  // d metres before the ice, braking at 8 m/s^2 on the dry part
  for (double d : {5.0, 20.0, 40.0}) {
    const double v = std::min(dry, std::sqrt(on_ice * on_ice + 2.0 * 8.0 * d));
    EXPECT_NEAR(p.at(600.0 - d), v, 0.02 * v) << d << " m before the ice";
  }
  // far from the ice, the straight's own cap (a flying profile: no start
  // from rest)
  EXPECT_NEAR(p.at(100.0), dry, 1e-9);
}

}  // namespace
}  // namespace groundsim::drivers
