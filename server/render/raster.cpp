#include "render/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

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

// v's fractional part, v - floor(v), for |v| below 2^62 (a ground patch's
// metres): a truncation, not libm's floor (baseline x86-64 has no rounding
// instruction, and this runs for every ground pixel)
double frac(double v) {
  double f = static_cast<double>(static_cast<long long>(v));
  if (f > v) f -= 1.0;
  return v - f;
}

// Which of the texture's colours (kGround) lies at world x, y.
enum GroundColour { kGrassColour, kEdgeColour, kHalfColour };
constexpr std::array<Rgb, 3> kGround{kGrass, kEdge, kHalf};
int groundAt(double x, double y) {
  const double fx = frac(x), fy = frac(y);
  const double edge_w = 3.0 / 256.0, half_w = 1.0 / 256.0;  // the canvas' line widths over its 256 px
  if (fx < edge_w || fx > 1.0 - edge_w || fy < edge_w || fy > 1.0 - edge_w) return kEdgeColour;
  if (std::abs(fx - 0.5) < half_w || std::abs(fy - 0.5) < half_w) return kHalfColour;
  return kGrassColour;
}

std::uint8_t byteOf(double v) { return static_cast<std::uint8_t>(std::clamp(v * 255.0 + 0.5, 0.0, 255.0)); }

// A colour's bytes, made once for a triangle's pixels that are not fogged.
using Bytes = std::array<std::uint8_t, 3>;
Bytes bytesOf(const Rgb& c) { return {byteOf(c.r), byteOf(c.g), byteOf(c.b)}; }

}  // namespace

Rgb rgbOf(std::uint32_t hex) {
  return {((hex >> 16) & 0xff) / 255.0, ((hex >> 8) & 0xff) / 255.0, (hex & 0xff) / 255.0};
}

Raster::Raster(int width, int height, double fov_deg)
    : width_(width), height_(height),
      focal_(0.5 * height / std::tan(0.5 * fov_deg * std::acos(-1.0) / 180.0)),
      colour_(static_cast<size_t>(width) * height * 3),
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
  const std::uint8_t r = byteOf(sky.r), g = byteOf(sky.g), b = byteOf(sky.b);
  for (size_t k = 0; k < colour_.size(); k += 3) colour_[k] = r, colour_[k + 1] = g, colour_[k + 2] = b;
  std::fill(depth_.begin(), depth_.end(), 0.0);  // 1 / depth: nothing drawn is infinitely far
}

Raster::Vertex Raster::project(const Vec3& cam, const Vec3& world) const {
  const double inv = 1.0 / cam.z();
  return {0.5 * width_ + focal_ * cam.x() * inv, 0.5 * height_ - focal_ * cam.y() * inv, inv, world.x() * inv,
          world.y() * inv};
}

void Raster::triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& colour, bool grid) {
  const Vec3 ca = toCamera(a), cb = toCamera(b), cc = toCamera(c);
  if (outside(ca, cb, cc)) return;
  triangle(a, b, c, ca, cb, cc, colour, grid);
}

bool Raster::outside(const Vec3& a, const Vec3& b, const Vec3& c) const {
  if (a.z() < kNear && b.z() < kNear && c.z() < kNear) return true;
  // the frame's sides through the eye: x = +-(w/2) z / focal, y = +-(h/2) z / focal (a pixel of margin)
  const double sx = (0.5 * width_ + 1.0) / focal_, sy = (0.5 * height_ + 1.0) / focal_;
  auto beyond = [](double u, double z, double slope) { return u > slope * z; };
  if (beyond(a.x(), a.z(), sx) && beyond(b.x(), b.z(), sx) && beyond(c.x(), c.z(), sx)) return true;
  if (beyond(-a.x(), a.z(), sx) && beyond(-b.x(), b.z(), sx) && beyond(-c.x(), c.z(), sx)) return true;
  if (beyond(a.y(), a.z(), sy) && beyond(b.y(), b.z(), sy) && beyond(c.y(), c.z(), sy)) return true;
  if (beyond(-a.y(), a.z(), sy) && beyond(-b.y(), b.z(), sy) && beyond(-c.y(), c.z(), sy)) return true;
  // beyond the fog's end: drawn as sky
  return a.z() > kFogEnd && b.z() > kFogEnd && c.z() > kFogEnd;
}

void Raster::triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& ca, const Vec3& cb, const Vec3& cc,
                      const Rgb& colour, bool grid) {
  // two-sided Lambert light: the normal turned towards the camera
  Vec3 n = (b - a).cross(c - a);
  const double nn = n.norm();
  if (!(nn > 0.0)) return;
  n /= nn;
  if (n.dot(eye_ - a) < 0.0) n = -n;
  const double light = 0.45 + 0.55 * std::max(0.0, n.dot(kSun));
  const Rgb lit{colour.r * light, colour.g * light, colour.b * light};
  // clipped by the near plane (a polygon of up to 4)
  const std::array<Vec3, 3> world = {a, b, c};
  const std::array<Vec3, 3> cam = {ca, cb, cc};
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
  // the pixels whose centres can be inside: the bounding box's, rounded outwards
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}) - 0.5)));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}) - 0.5)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}) - 0.5)));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}) - 0.5)));
  if (x0 > x1 || y0 > y1) return;
  // barycentric weights from the edge functions, linear in x and y: their
  // values at the box's first pixel centre, then a step per pixel and per row
  const double inv_area = 1.0 / area;
  const double dwa_dx = (b.y - c.y) * inv_area, dwa_dy = (c.x - b.x) * inv_area;
  const double dwb_dx = (c.y - a.y) * inv_area, dwb_dy = (a.x - c.x) * inv_area;
  const double xs = x0 + 0.5, ys = y0 + 0.5;
  double wa_row = ((b.x - xs) * (c.y - ys) - (b.y - ys) * (c.x - xs)) * inv_area;
  double wb_row = ((c.x - xs) * (a.y - ys) - (c.y - ys) * (a.x - xs)) * inv_area;
  constexpr double kFogStartInv = 1.0 / kFogStart;
  const int last = x1 - x0;
  // the unfogged pixels' bytes, made once: the triangle's colour, or the
  // ground's three lit by it (the ground passes white: lit.r is the light)
  const double light = lit.r;
  const Bytes own = bytesOf(lit);
  std::array<Bytes, 3> ground{};
  if (grid)
    for (size_t g = 0; g < ground.size(); ++g)
      ground[g] = bytesOf({kGround[g].r * light, kGround[g].g * light, kGround[g].b * light});
  for (int py = y0; py <= y1; ++py, wa_row += dwa_dy, wb_row += dwb_dy) {
    // the row's pixels inside: where each weight w0 + dw i (i from the box's
    // first pixel) is >= 0, intersected; the third weight is 1 - wa - wb
    int lo = 0, hi = last;
    const double wc_row = 1.0 - wa_row - wb_row, dwc_dx = -dwa_dx - dwb_dx;
    for (const auto [w0, dw] : {std::pair{wa_row, dwa_dx}, std::pair{wb_row, dwb_dx}, std::pair{wc_row, dwc_dx}}) {
      if (dw > 0.0) {
        lo = std::max(lo, static_cast<int>(std::ceil(std::clamp(-w0 / dw, -1.0, last + 1.0))));
      } else if (dw < 0.0) {
        hi = std::min(hi, static_cast<int>(std::floor(std::clamp(w0 / -dw, -1.0, last + 1.0))));
      } else if (w0 < 0.0) {
        hi = -1;
      }
    }
    if (lo > hi) continue;
    const size_t row = static_cast<size_t>(py) * width_;
    for (int i = lo; i <= hi; ++i) {
      const int px = x0 + i;
      // at the span's ends a weight may be a rounding below 0: clamped
      const double wa = std::max(0.0, wa_row + dwa_dx * i), wb = std::max(0.0, wb_row + dwb_dx * i);
      const double wc = std::max(0.0, 1.0 - wa - wb);
      // nearer: a larger 1 / depth (the buffer holds 1 / depth; no division for a hidden pixel)
      const double inv_z = wa * a.inv_z + wb * b.inv_z + wc * c.inv_z;
      const size_t k = row + px;
      if (!(inv_z > depth_[k])) continue;
      depth_[k] = inv_z;
      if (!grid && inv_z >= kFogStartInv) {  // unfogged, its own colour: no depth needed
        put(k, own);
        continue;
      }
      const double z = 1.0 / inv_z;
      Rgb col = lit;
      int g = 0;
      if (grid) {
        g = groundAt((wa * a.wx + wb * b.wx + wc * c.wx) * z, (wa * a.wy + wb * b.wy + wc * c.wy) * z);
        col = {kGround[static_cast<size_t>(g)].r * light, kGround[static_cast<size_t>(g)].g * light,
               kGround[static_cast<size_t>(g)].b * light};
      }
      if (z <= kFogStart) {
        put(k, grid ? ground[static_cast<size_t>(g)] : own);
        continue;
      }
      const double f = std::min((z - kFogStart) * kFogScale, 1.0);
      put(k, Rgb{col.r + f * (sky_.r - col.r), col.g + f * (sky_.g - col.g), col.b + f * (sky_.b - col.b)});
    }
  }
}

void Raster::put(size_t k, const Rgb& c) { put(k, bytesOf(c)); }

void Raster::put(size_t k, const std::array<std::uint8_t, 3>& bytes) {
  std::uint8_t* p = colour_.data() + 3 * k;
  p[0] = bytes[0], p[1] = bytes[1], p[2] = bytes[2];
}

void Raster::write(std::uint8_t* rgb) const { std::copy(colour_.begin(), colour_.end(), rgb); }

}  // namespace groundsim::render
