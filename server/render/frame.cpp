#include "render/frame.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "physics/collision/collision.hpp"
#include "render/raster.hpp"

namespace groundsim::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kRound = 12;  // segments of a round shape's circle

// web/src/main.js: the vehicles' colours in order, the sky; objects.js, vehicle.js
constexpr std::uint32_t kVehicleColours[] = {0xd94f3d, 0x3d7dd9, 0x4fbf5a, 0xe0a030,
                                             0xa05fd0, 0x40c0c0, 0xc0c040, 0xd070a0};
constexpr std::uint32_t kSky = 0x9fc4e0, kTyre = 0x222222, kCone = 0xff6a13, kStatic = 0x8a8f96,
                        kMovable = 0x3f7fbf;


// A triangle of the convex part centred at `centre`, its normal outward.
Tri outward(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& centre) {
  Vec3 n = (b - a).cross(c - a);
  if (n.dot(a + b + c - 3.0 * centre) < 0.0) n = -n;
  return Tri{{a, b, c}, n};
}

// The triangles of a shape in its own frame (boxes without their rounding).
void shapeTriangles(const Shape& s, std::vector<Tri>& out) {
  auto ring = [](double r, double z, int k) {
    const double a = 2.0 * kPi * k / kRound;
    return Vec3(r * std::cos(a), r * std::sin(a), z);
  };
  // a frustum along z from (r0 at z0) to (r1 at z1), capped
  auto frustum = [&](double r0, double z0, double r1, double z1) {
    for (int k = 0; k < kRound; ++k) {
      const Vec3 a = ring(r0, z0, k), b = ring(r0, z0, k + 1), c = ring(r1, z1, k + 1), d = ring(r1, z1, k);
      const Vec3 mid(0.0, 0.0, 0.5 * (z0 + z1));
      out.push_back(outward(a, b, c, mid));
      if (r1 > 0.0) out.push_back(outward(a, c, d, mid));
      out.push_back(outward(Vec3(0, 0, z0), b, a, mid));
      if (r1 > 0.0) out.push_back(outward(Vec3(0, 0, z1), d, c, mid));
    }
  };
  auto sphere = [&](double r, const Vec3& centre) {
    const int rows = kRound / 2;
    auto at = [&](int i, int k) {
      const double th = kPi * i / rows, a = 2.0 * kPi * k / kRound;
      return Vec3(centre + r * Vec3(std::sin(th) * std::cos(a), std::sin(th) * std::sin(a), std::cos(th)));
    };
    for (int i = 0; i < rows; ++i)
      for (int k = 0; k < kRound; ++k) {
        out.push_back(outward(at(i, k), at(i + 1, k), at(i + 1, k + 1), centre));
        out.push_back(outward(at(i, k), at(i + 1, k + 1), at(i, k + 1), centre));
      }
  };
  switch (s.kind) {
    case ShapeKind::Box: {
      const Vec3 h = s.half;
      auto corner = [&](int i) { return Vec3((i & 1 ? 1 : -1) * h.x(), (i & 2 ? 1 : -1) * h.y(), (i & 4 ? 1 : -1) * h.z()); };
      static const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
      for (const auto& f : faces) {
        out.push_back(outward(corner(f[0]), corner(f[1]), corner(f[2]), Vec3::Zero()));
        out.push_back(outward(corner(f[0]), corner(f[2]), corner(f[3]), Vec3::Zero()));
      }
      break;
    }
    case ShapeKind::Sphere: sphere(s.radius, Vec3::Zero()); break;
    case ShapeKind::Cylinder: frustum(s.radius, -s.half_height, s.radius, s.half_height); break;
    case ShapeKind::Capsule:
      frustum(s.radius, -s.half_height, s.radius, s.half_height);
      sphere(s.radius, Vec3(0, 0, -s.half_height));
      sphere(s.radius, Vec3(0, 0, s.half_height));
      break;
    case ShapeKind::Cone: frustum(s.radius, -s.half_height, s.top_radius, s.half_height); break;
  }
}

Rgb colourOf(const Model& m, const Collider& c) {
  const CollisionGroup& g = m.groups[static_cast<size_t>(c.group)];
  if (g.vehicle >= 0)
    return rgbOf(c.shape.kind == ShapeKind::Cylinder ? kTyre : kVehicleColours[g.vehicle % 8]);
  if (c.shape.kind == ShapeKind::Cone) return rgbOf(kCone);
  return rgbOf(g.mass > 0.0 ? kMovable : kStatic);
}

// The ground patch: on a level plane row by row (Raster::levelGround); on
// another plane its two corner triangles (the grid is
// drawn from each pixel's world x and y, so they give the grid's pixels,
// without its 2 n^2 triangles' setup); else each cell's two triangles,
// every vertex to the camera once (a vertex is shared by up to six).
void drawGround(Raster& raster, FrameCache& cache) {
  const int n = cache.n;
  const std::vector<Vec3>& p = cache.ground;
  const Rgb white{1.0, 1.0, 1.0};
  if (cache.planar && cache.level) {
    const Vec3 &lo = p.front(), &hi = p.back();
    raster.levelGround(lo.z(), lo.x(), hi.x(), lo.y(), hi.y());
    return;
  }
  if (cache.planar) {
    const size_t a = 0, b = static_cast<size_t>(n) - 1, cc = static_cast<size_t>(n - 1) * n, d = cc + n - 1;
    raster.triangle(p[a], p[b], p[d], white, true);
    raster.triangle(p[a], p[d], p[cc], white, true);
    return;
  }
  const std::vector<unsigned char>& found = cache.found;
  cache.camera.resize(p.size());
  for (size_t k = 0; k < p.size(); ++k) cache.camera[k] = raster.toCamera(p[k]);
  const std::vector<Vec3>& q = cache.camera;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const size_t a = static_cast<size_t>(i) * n + j, b = a + 1, cc = a + n, d = cc + 1;
      if (!(found[a] && found[b] && found[cc] && found[d])) continue;
      if (!raster.outside(q[a], q[b], q[d])) raster.triangle(p[a], p[b], p[d], q[a], q[b], q[d], white, true);
      if (!raster.outside(q[a], q[d], q[cc])) raster.triangle(p[a], p[d], p[cc], q[a], q[d], q[cc], white, true);
    }
}

}  // namespace

void renderFrame(const Model& m, const State& s, GroundProbe& ground, int follow, const FrameOptions& o,
                 Raster& raster, FrameCache& cache, std::uint8_t* rgb) {
  const Eigen::VectorXd& y = s.y;
  const Vec3 c = bodyPos(y, follow);
  const Mat3 R = Quat(bodyRot(y, follow)).normalized().toRotationMatrix();
  Vec3 heading(R(0, 0), R(1, 0), 0.0);
  heading = heading.norm() > 1e-9 ? Vec3(heading.normalized()) : Vec3(Vec3::UnitX());
  const Vec3 target = c + 2.0 * heading + Vec3(0, 0, 0.5);
  const Vec3 eye = c - o.behind * heading + Vec3(0, 0, o.above);

  raster.look(eye, target);
  raster.clear(rgbOf(kSky), rgb);

  // the ground: a patch sampled on a grid fixed to the world (so it does not
  // swim as the camera moves), centred ahead of the car
  const double step = o.ground_step;
  const int n = std::max(2, static_cast<int>(std::ceil(o.ground_extent / step)) + 1);
  const Vec3 centre = c + 0.4 * o.ground_extent * heading;
  const double x0 = std::floor(centre.x() / step - 0.5 * (n - 1)) * step;
  const double y0 = std::floor(centre.y() / step - 0.5 * (n - 1)) * step;
  if (cache.n != n || cache.step != step || cache.x0 != x0 || cache.y0 != y0) {
    cache.n = n;
    cache.step = step;
    cache.x0 = x0;
    cache.y0 = y0;
    cache.ground.assign(static_cast<size_t>(n) * n, Vec3::Zero());
    cache.found.assign(cache.ground.size(), 0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        Vec3 point, normal;
        const size_t k = static_cast<size_t>(i) * n + j;
        cache.found[k] = groundPointBelow(ground, x0 + j * step, y0 + i * step, &point, &normal) ? 1 : 0;
        cache.ground[k] = point;
      }
    Vec3 plane_n;
    double plane_offset = 0.0;
    cache.planar = m.ground && m.ground->asPlane(&plane_n, &plane_offset) &&
                   std::all_of(cache.found.begin(), cache.found.end(), [](unsigned char f) { return f != 0; });
    cache.level = cache.planar && plane_n.x() == 0.0 && plane_n.y() == 0.0;
  }
  drawGround(raster, cache);

  // every collider in its body's pose (static ones in the world), its
  // triangles made again only when its shape is not the one they were made of
  cache.shapes.resize(m.colliders.size());
  cache.shape_of.resize(m.colliders.size());
  for (size_t k = 0; k < m.colliders.size(); ++k) {
    const Shape &now = m.colliders[k].shape, &was = cache.shape_of[k];
    if (!cache.shapes[k].empty() && now.kind == was.kind && now.half == was.half && now.radius == was.radius &&
        now.half_height == was.half_height && now.top_radius == was.top_radius)
      continue;
    cache.shape_of[k] = now;
    cache.shapes[k].clear();
    shapeTriangles(now, cache.shapes[k]);
  }
  for (size_t k = 0; k < m.colliders.size(); ++k) {
    const Collider& col = m.colliders[k];
    Mat3 rot = col.rot;
    Vec3 pos = col.pos;
    if (col.body >= 0) {
      const Mat3 Rb = Quat(bodyRot(y, col.body)).normalized().toRotationMatrix();
      rot = Rb * col.rot;
      pos = Vec3(bodyPos(y, col.body)) + Rb * col.pos;
    }
    // far beyond the fog: nothing to draw
    const double from_eye = (pos - eye).norm();
    if (from_eye > 80.0 + col.shape.bound()) continue;
    const Rgb colour = colourOf(m, col);
    // the eye outside the shape's bounding sphere: its back faces are hidden
    const bool cull = from_eye > col.shape.bound();
    for (const Tri& t : cache.shapes[k]) {
      const Vec3 a = pos + rot * t.v[0];
      if (cull && (rot * t.out).dot(eye - a) < 0.0) continue;
      raster.triangle(a, pos + rot * t.v[1], pos + rot * t.v[2], colour);
    }
  }
}

}  // namespace groundsim::render
