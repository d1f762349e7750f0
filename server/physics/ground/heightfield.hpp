// A ground given as a grid of heights: H(x, y, z) = z - h(x, y).
//
// h is the interpolating cubic B-spline of the samples (C2: its gradient and
// curvature are continuous across cell edges, so penalty contact sees no
// kinks; error O(cell^4) against the smooth surface sampled). At load the
// samples are turned in place into the spline's coefficients (a recursive
// prefilter along x, then along y), so memory is one float per sample and
// evaluation reads a 4 x 4 block.
//
// Edges: the spline uses mirror boundary conditions, so its slope normal to
// an edge is zero on the edge; beyond the grid the surface continues flat at
// the edge's heights (x and y are clamped to the grid), and the gradient
// stays continuous there. Near an edge (about 3 cells) a sloped grid bends
// flat to meet that continuation.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "physics/ground/ground.hpp"

namespace groundsim {

// Samples of a heightfield: heights[j * nx + i] is the height (m) at
// (x0 + i * cell, y0 + j * cell). nx, ny >= 2, cell > 0, all finite.
struct HeightSamples {
  int nx = 0, ny = 0;
  double cell = 1.0;            // m
  double x0 = 0.0, y0 = 0.0;    // m, position of sample (0, 0)
  std::vector<float> heights;   // m, nx * ny, row per y
};

class HeightfieldGround final : public Ground {
 public:
  // Takes the samples (their storage becomes the coefficients). Throws
  // std::invalid_argument for sizes or values outside the rules above.
  explicit HeightfieldGround(HeightSamples samples);

  double eval(const Vec3& p, Vec3* grad) const override;
  void heights(const double* x, const double* y, const double* z, int begin, int end,
               double* H) const override;
  // sqrt(1 + Gx^2 + Gy^2), with Gx, Gy the largest coefficient differences
  // over a cell: the spline's slope is a convex combination of them, so
  // this bounds |grad H| everywhere (computed once, at construction).
  double gradientBound() const override { return gradient_bound_; }
  std::string describe() const override;

  // h(x, y) and, when given, its partial derivatives.
  double height(double x, double y, double* dhdx = nullptr, double* dhdy = nullptr) const;
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  double cell() const { return cell_; }
  double x0() const { return x0_; }
  double y0() const { return y0_; }
  // Largest |grad h| (slope) the bound allows.
  double maxSlope() const;
  std::size_t bytes() const { return coef_.capacity() * sizeof(float); }
  // its content (with nx, ny, cell, x0, y0): what identifies the ground
  const std::vector<float>& coefficients() const { return coef_; }

 private:
  template <bool kGrad>
  double evaluate(double x, double y, double* dhdx, double* dhdy) const;

  int nx_, ny_;
  double cell_, inv_cell_, x0_, y0_;
  std::vector<float> coef_;  // B-spline coefficients, same layout as the samples
  double gradient_bound_ = 1.0;
};

}  // namespace groundsim
