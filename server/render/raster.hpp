// A small z-buffered triangle rasteriser for off-screen frames (render/):
// perspective camera, near-plane clipping, flat Lambert shading, distance
// fog, and a ground mode that draws the page's 1 m grid from the world
// coordinates of each pixel. Written out rather than taken from Mesa
// (OSMesa/EGL + llvmpipe) for two reasons measured against the issue's
// targets: a frame of a few thousand triangles at 160 x 120 costs about a
// tenth of a millisecond here, and the same state gives the same bytes on
// every machine (plain double arithmetic in a fixed order, one thread; the
// spans four pixels at a time where the CPU has AVX2 do the same operations
// without FMA: the same bytes, Render.WideSpansGiveThePixelLoopsBytes).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "physics/base/math.hpp"

namespace groundsim::render {

struct Rgb {
  double r = 0.0, g = 0.0, b = 0.0;  // linear 0..1
};
Rgb rgbOf(std::uint32_t hex);  // 0xRRGGBB

class Raster {
 public:
  Raster(int width, int height, double fov_deg = 60.0);  // px, vertical degrees
  // A camera at eye looking at target, z up.
  void look(const Vec3& eye, const Vec3& target);
  // Starts a frame drawn into rgb (height() x width() x 3 bytes, RGB, the
  // top row first: the caller's, written directly), cleared to the sky.
  void clear(const Rgb& sky, std::uint8_t* rgb);
  // One triangle (world coordinates) of colour c, lit from the sun; with
  // grid, the colour comes from the page's ground texture at each pixel's
  // world x, y instead.
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& colour, bool grid = false);
  // A point in camera coordinates (x right, y up, z along the view).
  Vec3 toCamera(const Vec3& world) const {
    const Vec3 d = world - eye_;
    return {d.dot(right_), d.dot(up_), d.dot(forward_)};
  }
  // Whether a triangle whose corners are at these camera coordinates lies
  // wholly outside the view (behind the near plane, or beyond one side of
  // the frame): nothing of it can be drawn.
  bool outside(const Vec3& a, const Vec3& b, const Vec3& c) const;
  // triangle() with its corners' camera coordinates already known (a mesh
  // whose vertices are shared: each transformed once).
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& ca, const Vec3& cb, const Vec3& cc,
                const Rgb& colour, bool grid = false);
  // The ground as the level plane z = height over the rectangle [x_lo, x_hi]
  // x [y_lo, y_hi], drawn first onto a cleared frame (no depth test): what
  // the rectangle's two triangles draw, without them. The camera has no roll
  // (look()), so a row of pixels sees a level plane at one depth: the row's
  // depth, fog and three lit colours are made once, and its pixels differ
  // only in their world x, y (affine along the row), from which the grid's
  // colour comes. Rows above the horizon, nearer than the near plane or
  // beyond the fog's end are left to the sky.
  void levelGround(double height, double x_lo, double x_hi, double y_lo, double y_hi);
  int width() const { return width_; }
  int height() const { return height_; }
  // Spans four pixels at a time (AVX2, where the CPU has it: the default)
  // or one by one; the bytes are the same (a test compares them).
  void setWideSpans(bool wide) { wide_ = wide; }

 private:
  struct Vertex {
    double x, y, inv_z;   // screen position, 1 / camera depth
    double wx, wy;        // world x, y divided by the depth (perspective-correct interpolation)
  };
  void fill(const Vertex& a, const Vertex& b, const Vertex& c, const Rgb& lit, bool grid);
  Vertex project(const Vec3& camera, const Vec3& world) const;

  int width_, height_;
  double focal_;          // px
  Vec3 eye_ = Vec3::Zero(), right_ = Vec3::UnitX(), up_ = Vec3::UnitZ(), forward_ = Vec3::UnitY();
  Rgb sky_;
  void put(size_t pixel, const Rgb& c);  // the pixel's colour, as bytes
  void put(size_t pixel, const std::array<std::uint8_t, 3>& bytes);
  std::uint8_t* colour_ = nullptr;       // the frame's RGB bytes, the caller's (clear())
  std::vector<double> depth_;  // 1 / depth of what each pixel shows (0: sky)
  bool wide_;                  // spans four pixels at a time (spanQuads in raster.cpp)
};

}  // namespace groundsim::render
