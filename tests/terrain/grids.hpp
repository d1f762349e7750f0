// Heightfields sampled from functions, for the terrain tests.
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>

#include "physics/ground/heightfield.hpp"

namespace groundsim::test {

inline constexpr double kPi = std::numbers::pi;

// Samples f over [x0, x1] x [y0, y1] with the given cell (the far ends are
// rounded up to whole cells).
inline HeightSamples sample(const std::function<double(double, double)>& f, double x0, double x1, double y0,
                            double y1, double cell) {
  HeightSamples s;
  s.nx = static_cast<int>(std::ceil((x1 - x0) / cell - 1e-9)) + 1;
  s.ny = static_cast<int>(std::ceil((y1 - y0) / cell - 1e-9)) + 1;
  s.cell = cell;
  s.x0 = x0;
  s.y0 = y0;
  s.heights.resize(static_cast<size_t>(s.nx) * s.ny);
  for (int j = 0; j < s.ny; ++j)
    for (int i = 0; i < s.nx; ++i) s.heights[j * s.nx + i] = static_cast<float>(f(x0 + i * cell, y0 + j * cell));
  return s;
}

inline std::shared_ptr<HeightfieldGround> sampledGround(const std::function<double(double, double)>& f, double x0,
                                                        double x1, double y0, double y1, double cell) {
  return std::make_shared<HeightfieldGround>(sample(f, x0, x1, y0, y1, cell));
}

}  // namespace groundsim::test
