#include "scenario/footprint.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "physics/collision/collision_build.hpp"

namespace groundsim::scenario {
namespace {

struct Rect {
  double cx = 0.0, cy = 0.0;  // centre of the rectangle (m)
  double ux = 1.0, uy = 0.0;  // heading
  double hl = 0.0, hw = 0.0;  // half length, half width
};

// The rectangle in the ground plane: its centre is offset along the
// heading when the vehicle reaches further ahead than behind.
Rect placed(const VehicleSpec& v) {
  const Footprint f = vehicleRectangle(v);
  Rect r;
  r.ux = std::cos(v.placement.yaw);
  r.uy = std::sin(v.placement.yaw);
  const double off = 0.5 * (f.front - f.back);
  r.cx = v.placement.position.x() + off * r.ux;
  r.cy = v.placement.position.y() + off * r.uy;
  r.hl = 0.5 * (f.front + f.back);
  r.hw = f.half_width;
  return r;
}

// Half the rectangle's extent along unit axis (ax, ay).
double reach(const Rect& r, double ax, double ay) {
  return r.hl * std::abs(r.ux * ax + r.uy * ay) + r.hw * std::abs(-r.uy * ax + r.ux * ay);
}

}  // namespace

Footprint vehicleRectangle(const VehicleSpec& v) {
  Footprint f;
  if (v.road_car) {
    const RoadCarParams& p = v.road;
    const Vec3 body = roadCarBodySize(p);
    // the axles' midpoint, ahead of the centre of mass (negative: behind)
    const double mid = p.cg_to_front - 0.5 * p.wheelbase;
    f.front = std::max(p.cg_to_front + p.wheel_radius, mid + 0.5 * body.x());
    f.back = std::max(p.wheelbase - p.cg_to_front + p.wheel_radius, 0.5 * body.x() - mid);
    // 0.1 m: half a 0.2 m tyre outside the track
    f.half_width = std::max(0.5 * p.track + 0.1, 0.5 * body.y());
    return f;
  }
  const CarParams& p = v.params;
  f.front = f.back = p.half_length + p.wheel_radius;
  f.half_width = p.half_width + p.axle_half_length;
  return f;
}

double vehicleFootprint(const VehicleSpec& v) {
  const Footprint f = vehicleRectangle(v);
  return std::hypot(std::max(f.front, f.back), f.half_width);
}

bool footprintsOverlap(const VehicleSpec& a, const VehicleSpec& b) {
  const Rect ra = placed(a), rb = placed(b);
  const double dx = rb.cx - ra.cx, dy = rb.cy - ra.cy;
  const std::array<std::array<double, 2>, 4> axes{{{ra.ux, ra.uy}, {-ra.uy, ra.ux}, {rb.ux, rb.uy}, {-rb.uy, rb.ux}}};
  for (const auto& [ax, ay] : axes)
    if (std::abs(dx * ax + dy * ay) > reach(ra, ax, ay) + reach(rb, ax, ay)) return false;
  return true;
}

}  // namespace groundsim::scenario
