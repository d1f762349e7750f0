// Friction that depends on the place: patches (rectangles, circles) and a
// friction map (a grid of mu, bilinear) laid over any ground. The contact
// code asks Ground::friction(p, scene_mu) at each contact point; a ground
// wrapped here answers, in order: the last patch containing (p.x, p.y), else
// the map where (p.x, p.y) lies on it, else scene_mu. Shape and height are
// the wrapped ground's, unchanged.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "physics/ground/ground.hpp"

namespace groundsim {

struct FrictionPatch {
  enum class Shape { Rectangle, Circle };
  Shape shape = Shape::Rectangle;
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // m, rectangle corners (x0 <= x1, y0 <= y1)
  double cx = 0, cy = 0, radius = 0;      // m, circle
  double mu = 1.0;                        // -
  std::string name;                       // label for describe()
  bool contains(double x, double y) const;
};

// mu[j * nx + i] at (x0 + i * cell, y0 + j * cell), bilinear between
// samples; outside the grid the map has no say.
struct FrictionGrid {
  int nx = 0, ny = 0;
  double cell = 1.0, x0 = 0.0, y0 = 0.0;  // m
  std::vector<float> mu;
  bool empty() const { return mu.empty(); }
  // mu at (x, y), or a negative value off the grid
  double at(double x, double y) const;
};

// `ground` with place-dependent friction. Returns ground itself when there
// are neither patches nor a map.
GroundPtr withSurfaceFriction(GroundPtr ground, std::vector<FrictionPatch> patches,
                              std::shared_ptr<const FrictionGrid> map = nullptr);

}  // namespace groundsim
