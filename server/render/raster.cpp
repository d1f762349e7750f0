#include "render/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace groundsim::render {
namespace {

constexpr double kNear = 0.05;                   // m  near plane
constexpr double kFogStart = 30.0, kFogEnd = 70.0;  // m  as the page's THREE.Fog
constexpr double kFogScale = 1.0 / (kFogEnd - kFogStart);
const Vec3 kSun = Vec3(0.4, 0.3, 0.85).normalized();

// The page's ground texture (web/src/ground.js): grass with a dark line at
// every metre and a lighter one at every half metre.
constexpr Rgb kGrass{0x6f / 255.0, 0x8f / 255.0, 0x5a / 255.0}, kEdge{0x2f / 255.0, 0x3f / 255.0, 0x28 / 255.0},
    kHalf{0x4d / 255.0, 0x66 / 255.0, 0x40 / 255.0};

Rgb groundAt(double x, double y) {
  const Rgb &grass = kGrass, &edge = kEdge, &half = kHalf;
  auto frac = [](double v) { return v - std::floor(v); };
  const double fx = frac(x), fy = frac(y);
  const double edge_w = 3.0 / 256.0, half_w = 1.0 / 256.0;  // the canvas' line widths over its 256 px
  if (fx < edge_w || fx > 1.0 - edge_w || fy < edge_w || fy > 1.0 - edge_w) return edge;
  if (std::abs(fx - 0.5) < half_w || std::abs(fy - 0.5) < half_w) return half;
  return grass;
}

std::uint8_t byteOf(double v) { return static_cast<std::uint8_t>(std::clamp(v * 255.0 + 0.5, 0.0, 255.0)); }

}  // namespace

Rgb rgbOf(std::uint32_t hex) {
  return {((hex >> 16) & 0xff) / 255.0, ((hex >> 8) & 0xff) / 255.0, (hex & 0xff) / 255.0};
}

Raster::Raster(int width, int height, double fov_deg)
    : width_(width), height_(height),
      focal_(0.5 * height / std::tan(0.5 * fov_deg * std::acos(-1.0) / 180.0)),
      colour_(static_cast<size_t>(width) * height),
      depth_(static_cast<size_t>(width) * height) {}

void Raster::look(const Vec3& eye, const Vec3& target) {
  eye_ = eye;
  forward_ = (target - eye).normalized();
  Vec3 r = forward_.cross(Vec3::UnitZ());
  if (r.norm() < 1e-9) r = Vec3::UnitX();  // looking straight down or up
  right_ = r.normalized();
  up_ = right_.cross(forward_);
}

void Raster::clear(const Rgb& sky) {
  sky_ = sky;
  std::fill(colour_.begin(), colour_.end(), sky);
  std::fill(depth_.begin(), depth_.end(), std::numeric_limits<double>::infinity());
}

Raster::Vertex Raster::project(const Vec3& cam, const Vec3& world) const {
  const double inv = 1.0 / cam.z();
  return {0.5 * width_ + focal_ * cam.x() * inv, 0.5 * height_ - focal_ * cam.y() * inv, inv, world.x() * inv,
          world.y() * inv};
}

void Raster::triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& colour, bool grid) {
  // two-sided Lambert light: the normal turned towards the camera
  Vec3 n = (b - a).cross(c - a);
  const double nn = n.norm();
  if (!(nn > 0.0)) return;
  n /= nn;
  if (n.dot(eye_ - a) < 0.0) n = -n;
  const double light = 0.45 + 0.55 * std::max(0.0, n.dot(kSun));
  const Rgb lit{colour.r * light, colour.g * light, colour.b * light};
  // camera coordinates, then clipped by the near plane (a polygon of up to 4)
  std::array<Vec3, 3> world = {a, b, c};
  std::array<Vec3, 3> cam;
  for (int i = 0; i < 3; ++i) {
    const Vec3 d = world[i] - eye_;
    cam[i] = Vec3(d.dot(right_), d.dot(up_), d.dot(forward_));
  }
  std::array<Vec3, 4> pc, pw;
  int n_out = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const bool in_i = cam[i].z() >= kNear, in_j = cam[j].z() >= kNear;
    if (in_i) {
      pc[n_out] = cam[i];
      pw[n_out++] = world[i];
    }
    if (in_i != in_j) {
      const double t = (kNear - cam[i].z()) / (cam[j].z() - cam[i].z());
      pc[n_out] = cam[i] + t * (cam[j] - cam[i]);
      pw[n_out++] = world[i] + t * (world[j] - world[i]);
    }
  }
  if (n_out < 3) return;
  const Vertex v0 = project(pc[0], pw[0]);
  for (int i = 1; i + 1 < n_out; ++i) fill(v0, project(pc[i], pw[i]), project(pc[i + 1], pw[i + 1]), lit, grid);
}

void Raster::fill(const Vertex& a, const Vertex& b, const Vertex& c, const Rgb& lit, bool grid) {
  const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(std::abs(area) > 1e-12)) return;
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
  const double inv_area = 1.0 / area;
  const Vertex* v[3] = {&a, &b, &c};
  for (int py = y0; py <= y1; ++py) {
    const double y = py + 0.5;
    // the row's span inside the triangle: where it crosses the edges (a
    // pixel of margin; the weights below decide each pixel)
    double xl = std::numeric_limits<double>::infinity(), xr = -xl;
    for (int e = 0; e < 3; ++e) {
      const Vertex& p = *v[e];
      const Vertex& q = *v[(e + 1) % 3];
      if ((p.y - y) * (q.y - y) > 0.0) continue;
      const double x = p.y == q.y ? std::min(p.x, q.x) : p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
      const double x2 = p.y == q.y ? std::max(p.x, q.x) : x;
      xl = std::min(xl, x);
      xr = std::max(xr, x2);
    }
    if (!(xl <= xr)) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(xl - 1.0)));
    const int x1 = std::min(width_ - 1, static_cast<int>(std::ceil(xr + 1.0)));
    // barycentric weights from the edge functions, linear in x along the
    // row: their values at the first pixel's centre, then a step per pixel
    const double xs = x0 + 0.5;
    const double dwa = (b.y - c.y) * inv_area, dwb = (c.y - a.y) * inv_area;
    double wa = ((b.x - xs) * (c.y - y) - (b.y - y) * (c.x - xs)) * inv_area;
    double wb = ((c.x - xs) * (a.y - y) - (c.y - y) * (a.x - xs)) * inv_area;
    for (int px = x0; px <= x1; ++px, wa += dwa, wb += dwb) {
      const double wc = 1.0 - wa - wb;
      if (wa < 0.0 || wb < 0.0 || wc < 0.0) continue;
      const double inv_z = wa * a.inv_z + wb * b.inv_z + wc * c.inv_z;
      const double z = 1.0 / inv_z;
      const size_t k = static_cast<size_t>(py) * width_ + px;
      if (!(z < depth_[k])) continue;
      depth_[k] = z;
      Rgb col = lit;
      if (grid) {
        const Rgb g = groundAt((wa * a.wx + wb * b.wx + wc * c.wx) * z, (wa * a.wy + wb * b.wy + wc * c.wy) * z);
        const double light = lit.r;  // the ground passes white as its colour: lit.r is the light
        col = {g.r * light, g.g * light, g.b * light};
      }
      if (z <= kFogStart) {
        colour_[k] = col;
        continue;
      }
      const double f = std::min((z - kFogStart) * kFogScale, 1.0);
      colour_[k] = {col.r + f * (sky_.r - col.r), col.g + f * (sky_.g - col.g), col.b + f * (sky_.b - col.b)};
    }
  }
}

void Raster::write(std::uint8_t* rgb) const {
  for (size_t k = 0; k < colour_.size(); ++k) {
    rgb[3 * k] = byteOf(colour_[k].r);
    rgb[3 * k + 1] = byteOf(colour_[k].g);
    rgb[3 * k + 2] = byteOf(colour_[k].b);
  }
}

}  // namespace groundsim::render
