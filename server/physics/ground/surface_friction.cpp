#include "physics/ground/surface_friction.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace groundsim {

bool FrictionPatch::contains(double x, double y) const {
  if (shape == Shape::Circle) {
    const double dx = x - cx, dy = y - cy;
    return dx * dx + dy * dy <= radius * radius;
  }
  return x >= x0 && x <= x1 && y >= y0 && y <= y1;
}

double FrictionGrid::at(double x, double y) const {
  if (mu.empty()) return -1.0;
  const double u = (x - x0) / cell, v = (y - y0) / cell;
  if (!(u >= 0.0 && v >= 0.0 && u <= nx - 1 && v <= ny - 1)) return -1.0;
  const int i = std::min(static_cast<int>(u), nx - 2), j = std::min(static_cast<int>(v), ny - 2);
  const double s = u - i, t = v - j;
  const float* r0 = mu.data() + static_cast<std::size_t>(j) * nx + i;
  const float* r1 = r0 + nx;
  return (1 - t) * ((1 - s) * r0[0] + s * r0[1]) + t * ((1 - s) * r1[0] + s * r1[1]);
}

namespace {

class SurfaceFriction final : public Ground {
 public:
  SurfaceFriction(GroundPtr g, std::vector<FrictionPatch> p, std::shared_ptr<const FrictionGrid> m)
      : g_(std::move(g)), patches_(std::move(p)), map_(std::move(m)) {}
  double eval(const Vec3& p, Vec3* grad) const override { return g_->eval(p, grad); }
  void heights(const double* x, const double* y, const double* z, int begin, int end,
               double* H) const override {
    g_->heights(x, y, z, begin, end, H);
  }
  double gradientBound() const override { return g_->gradientBound(); }
  // the shape is the wrapped ground's, so is its evaluation state
  std::unique_ptr<GroundEvaluator> makeEvaluator() const override { return g_->makeEvaluator(); }
  double friction(const Vec3& p, double scene_mu) const override {
    for (auto it = patches_.rbegin(); it != patches_.rend(); ++it)
      if (it->contains(p.x(), p.y())) return it->mu;
    const double m = map_ ? map_->at(p.x(), p.y()) : -1.0;
    return m >= 0.0 ? m : g_->friction(p, scene_mu);
  }
  std::string describe() const override {
    std::ostringstream s;
    s << g_->describe();
    if (!patches_.empty()) s << ", " << patches_.size() << " friction patches";
    if (map_) s << ", friction map " << map_->nx << " x " << map_->ny;
    return s.str();
  }

 private:
  GroundPtr g_;
  std::vector<FrictionPatch> patches_;
  std::shared_ptr<const FrictionGrid> map_;
};

}  // namespace

GroundPtr withSurfaceFriction(GroundPtr ground, std::vector<FrictionPatch> patches,
                              std::shared_ptr<const FrictionGrid> map) {
  if (map && map->empty()) map = nullptr;
  if (patches.empty() && !map) return ground;
  return std::make_shared<SurfaceFriction>(std::move(ground), std::move(patches), std::move(map));
}

}  // namespace groundsim
