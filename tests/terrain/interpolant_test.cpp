// The heightfield's spline against its samples and against the smooth
// surfaces it was sampled from: exact at the samples, continuous gradient
// across cell edges, O(cell^4) convergence, exact gradient, a true slope
// bound, and the flat continuation beyond the edges.
#include <gtest/gtest.h>

#include <random>

#include "grids.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

HeightSamples noise(int nx, int ny, double cell, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  HeightSamples s;
  s.nx = nx;
  s.ny = ny;
  s.cell = cell;
  s.x0 = -3.0;
  s.y0 = 2.0;
  for (int k = 0; k < nx * ny; ++k) s.heights.push_back(u(rng));
  return s;
}

double cosine(double x, double) { return 0.5 * std::cos(x); }

// Largest height and slope error against 0.5 cos x over |x| <= 5, |y| <= 1
// (far from the grid's edges at +-10, +-3).
std::pair<double, double> cosineError(double cell) {
  auto g = sampledGround(cosine, -10, 10, -3, 3, cell);
  double eh = 0, eg = 0;
  for (int k = 0; k <= 2000; ++k) {
    const double x = -5.0 + 10.0 * k / 2000.0 + 1e-3, y = std::sin(k) * 1.0;
    double hx, hy;
    const double h = g->height(x, y, &hx, &hy);
    eh = std::max(eh, std::abs(h - 0.5 * std::cos(x)));
    eg = std::max(eg, std::hypot(hx + 0.5 * std::sin(x), hy));
  }
  return {eh, eg};
}

}  // namespace

TEST(Interpolant, ReproducesTheSamplesAtGridPoints) {
  const HeightSamples s = noise(37, 23, 0.25, 1);
  const HeightfieldGround g{HeightSamples(s)};
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i)
      ASSERT_NEAR(g.height(s.x0 + i * s.cell, s.y0 + j * s.cell), s.heights[j * s.nx + i], 2e-6)
          << "sample " << i << ", " << j;
  // and a 2 x 2 grid (the shortest mirror)
  HeightSamples t;
  t.nx = t.ny = 2;
  t.heights = {0.0f, 1.0f, 2.0f, 4.0f};
  const HeightfieldGround small{HeightSamples(t)};
  EXPECT_NEAR(small.height(0, 0), 0.0, 1e-6);
  EXPECT_NEAR(small.height(1, 0), 1.0, 1e-6);
  EXPECT_NEAR(small.height(0, 1), 2.0, 1e-6);
  EXPECT_NEAR(small.height(1, 1), 4.0, 1e-6);
}

TEST(Interpolant, GradientAndCurvatureAreContinuousAcrossCellEdges) {
  // random samples: the hardest case for a kink at the edges (bilinear
  // gradients jump by O(1) here)
  const HeightSamples s = noise(20, 20, 0.5, 2);
  const HeightfieldGround g{HeightSamples(s)};
  const double eps = 1e-7;
  double worst_jump = 0, worst_curv_jump = 0, typical = 0;
  for (int i = 1; i < s.nx - 1; ++i)
    for (int j = 1; j < s.ny - 1; ++j) {
      const double x = s.x0 + i * s.cell, y = s.y0 + (j + 0.37) * s.cell;
      double lx, ly, rx, ry;
      g.height(x - eps, y, &lx, &ly);
      g.height(x + eps, y, &rx, &ry);
      worst_jump = std::max(worst_jump, std::hypot(rx - lx, ry - ly));
      typical = std::max(typical, std::hypot(lx, ly));
      // second derivative from each side (C2 spline: equal)
      double l2x, r2x, dummy;
      g.height(x - 1e-3, y, &l2x, &dummy);
      g.height(x + 1e-3, y, &r2x, &dummy);
      const double left = (lx - l2x) / (1e-3 - eps), right = (r2x - rx) / (1e-3 - eps);
      worst_curv_jump = std::max(worst_curv_jump, std::abs(right - left));
      // across an edge of constant y too
      const double yy = s.y0 + j * s.cell, xx = s.x0 + (i + 0.61) * s.cell;
      g.height(xx, yy - eps, &lx, &ly);
      g.height(xx, yy + eps, &rx, &ry);
      worst_jump = std::max(worst_jump, std::hypot(rx - lx, ry - ly));
    }
  EXPECT_GT(typical, 0.5);                 // the field is rough
  EXPECT_LT(worst_jump, 1e-5 * typical);   // O(eps) differences only
  // curvature ~ 1 / cell^2 = 4 per metre here; its change over 2 mm is O(1e-2)
  EXPECT_LT(worst_curv_jump, 0.1);
}

TEST(Interpolant, GradientIsTheExactDerivativeOfTheHeight) {
  const HeightSamples s = noise(15, 12, 0.3, 3);
  const HeightfieldGround g{HeightSamples(s)};
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> ux(-3.0, -3.0 + 14 * 0.3), uy(2.0, 2.0 + 11 * 0.3);
  const double h = 1e-6;
  for (int k = 0; k < 500; ++k) {
    const double x = ux(rng), y = uy(rng);
    Vec3 grad;
    const double H = g.eval(Vec3(x, y, 0.7), &grad);
    EXPECT_NEAR(H, 0.7 - g.height(x, y), 1e-15);
    const double fx = -(g.height(x + h, y) - g.height(x - h, y)) / (2 * h);
    const double fy = -(g.height(x, y + h) - g.height(x, y - h)) / (2 * h);
    ASSERT_NEAR(grad.x(), fx, 1e-6) << x << ", " << y;
    ASSERT_NEAR(grad.y(), fy, 1e-6) << x << ", " << y;
    ASSERT_EQ(grad.z(), 1.0);
  }
}

TEST(Interpolant, ConvergesToTheSampledSurfaceAtFourthOrder) {
  const auto [e1, g1] = cosineError(0.4);
  const auto [e2, g2] = cosineError(0.2);
  const auto [e3, g3] = cosineError(0.1);
  // the cubic spline interpolant: height error ~ cell^4, slope error ~ cell^3
  std::printf("height errors %.3g %.3g %.3g, slope errors %.3g %.3g %.3g\n", e1, e2, e3, g1, g2, g3);
  EXPECT_NEAR(std::log2(e1 / e2), 4.0, 0.3) << e1 << " " << e2;
  EXPECT_NEAR(std::log2(e2 / e3), 4.0, 0.3) << e2 << " " << e3;
  EXPECT_NEAR(std::log2(g1 / g2), 3.0, 0.3) << g1 << " " << g2;
  EXPECT_NEAR(std::log2(g2 / g3), 3.0, 0.3) << g2 << " " << g3;
  // and small in absolute terms: 0.4 m cells already within 0.1 mm
  EXPECT_LT(e1, 1e-4);
}

TEST(Interpolant, AnInclineIsReproducedAwayFromTheEdges) {
  const double slope = std::tan(20 * kPi / 180);
  auto g = sampledGround([&](double x, double) { return -slope * x; }, -10, 30, -3, 3, 0.1);
  for (double x = -5; x <= 25; x += 0.0137) {
    double hx, hy;
    const double h = g->height(x, 0.3, &hx, &hy);
    ASSERT_NEAR(h, -slope * x, 5e-6) << x;  // float samples: 1e-6 relative
    ASSERT_NEAR(hx, -slope, 1e-4) << x;
    ASSERT_NEAR(hy, 0.0, 1e-4) << x;
  }
}

TEST(Interpolant, SlopeBoundHoldsEverywhereAndIsTight) {
  // cosine: true largest |grad H| is sqrt(1 + 0.5^2)
  auto g = sampledGround(cosine, -10, 10, -3, 3, 0.2);
  const double truth = std::sqrt(1.25);
  EXPECT_GE(g->gradientBound(), truth);
  EXPECT_LT(g->gradientBound(), 1.01 * truth);
  // random field: sampled everywhere, inside and beyond the edges
  const HeightfieldGround n{noise(30, 25, 0.2, 5)};
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> ux(-5.0, 5.0), uy(0.0, 9.0);
  double worst = 0;
  Vec3 grad;
  for (int k = 0; k < 200000; ++k) {
    n.eval(Vec3(ux(rng), uy(rng), 0), &grad);
    worst = std::max(worst, grad.norm());
  }
  EXPECT_LE(worst, n.gradientBound());
  // white noise is the bound's worst case (its spline coefficients swing
  // ~sqrt(3) wider than the samples, in alternating signs): here 4.6x the
  // true slope, against 1% for the smooth cosine above
  EXPECT_GT(worst, 0.15 * n.gradientBound());
}

TEST(Interpolant, BeyondTheEdgesTheSurfaceContinuesFlatWithAContinuousGradient) {
  const HeightSamples s = noise(12, 10, 0.5, 7);
  const HeightfieldGround g{HeightSamples(s)};
  const double x_end = s.x0 + (s.nx - 1) * s.cell, y_end = s.y0 + (s.ny - 1) * s.cell;
  for (double y : {s.y0 + 0.3, s.y0 + 2.1, y_end - 0.2}) {
    double hx_in, hy_in, hx_out, hy_out;
    const double edge = g.height(x_end - 1e-9, y, &hx_in, &hy_in);
    const double far = g.height(x_end + 7.0, y, &hx_out, &hy_out);
    EXPECT_NEAR(far, edge, 1e-8);       // clamped to the edge's height
    EXPECT_NEAR(hx_in, 0.0, 1e-6);      // the spline arrives flat...
    EXPECT_EQ(hx_out, 0.0);             // ...and stays flat
    EXPECT_NEAR(hy_out, hy_in, 1e-6);   // the slope along the edge carries on
    // the other edges
    EXPECT_NEAR(g.height(s.x0 - 3.0, y), g.height(s.x0, y), 1e-8);
  }
  EXPECT_NEAR(g.height(0.1, y_end + 1.0), g.height(0.1, y_end), 1e-8);
  EXPECT_NEAR(g.height(0.1, s.y0 - 1.0), g.height(0.1, s.y0), 1e-8);
  EXPECT_NEAR(g.height(-1e9, 1e9), g.height(s.x0, y_end), 1e-8);
}

TEST(Interpolant, RefusesGridsItCannotInterpolate) {
  HeightSamples s;
  s.nx = 1;
  s.ny = 3;
  s.heights = {0, 0, 0};
  EXPECT_THROW(HeightfieldGround{s}, std::invalid_argument);
  s.nx = 2;
  s.ny = 2;
  s.heights = {0, 0, 0};
  EXPECT_THROW(HeightfieldGround{s}, std::invalid_argument);
  s.heights = {0, 0, 0, std::nanf("")};
  EXPECT_THROW(HeightfieldGround{s}, std::invalid_argument);
  s.heights = {0, 0, 0, 0};
  s.cell = 0;
  EXPECT_THROW(HeightfieldGround{s}, std::invalid_argument);
}
