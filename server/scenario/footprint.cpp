#include "scenario/footprint.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "physics/build/collision_build.hpp"

namespace groundsim::scenario {
namespace {

struct Rect {
  double cx = 0.0, cy = 0.0;  // centre of the rectangle (m)
  double ux = 1.0, uy = 0.0;  // heading
  double hl = 0.0, hw = 0.0;  // half length, half width
};

// The rectangle in the ground plane: its centre is offset along the
// heading when the vehicle reaches further ahead than behind.
Rect placed(const VehicleSpec& v, const Footprint& f) {
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

bool footprintsOverlap(const VehicleSpec& a, const VehicleSpec& b) { return footprintsMayMeet(a, b, 0.0, 0.0, 0.0); }

namespace {

// The rectangle of a vehicle turned by up to `turn` (< pi/2) about its
// position: a point (x, y) of it (x along the heading) moves by at most
// |x| (1 - cos) + |y| sin along the heading and |x| sin + |y| (1 - cos)
// across it, so the rectangle grown by those at its farthest corner
// holds every turned one.
Footprint turned(Footprint f, double turn) {
  if (!(turn > 0.0)) return f;
  const double c = 1.0 - std::cos(turn), s = std::sin(turn), l = std::max(f.front, f.back), w = f.half_width;
  const double along = l * c + w * s, across = l * s + w * c;
  f.front += along;
  f.back += along;
  f.half_width += across;
  return f;
}

}  // namespace

bool footprintsMayMeet(const VehicleSpec& a, const VehicleSpec& b, double move_x, double move_y, double turn) {
  move_x = std::abs(move_x);
  move_y = std::abs(move_y);
  turn = std::abs(turn);
  // the circles about the rectangles hold them at any heading
  const double gap = std::hypot(b.placement.position.x() - a.placement.position.x(),
                                b.placement.position.y() - a.placement.position.y());
  if (gap - 2.0 * std::hypot(move_x, move_y) > vehicleFootprint(a) + vehicleFootprint(b)) return false;
  if (!(turn < 0.5 * 3.14159265358979323846)) return true;  // the circles decide
  const Rect ra = placed(a, turned(vehicleRectangle(a), turn)), rb = placed(b, turned(vehicleRectangle(b), turn));
  const double dx = rb.cx - ra.cx, dy = rb.cy - ra.cy;
  const std::array<std::array<double, 2>, 4> axes{{{ra.ux, ra.uy}, {-ra.uy, ra.ux}, {rb.ux, rb.uy}, {-rb.uy, rb.ux}}};
  // separated along an axis by more than both can move towards each other
  for (const auto& [ax, ay] : axes)
    if (std::abs(dx * ax + dy * ay) - 2.0 * (move_x * std::abs(ax) + move_y * std::abs(ay)) >
        reach(ra, ax, ay) + reach(rb, ax, ay))
      return false;
  return true;
}

}  // namespace groundsim::scenario
