#include "physics/collision/shape.hpp"

#include <algorithm>
#include <cmath>

namespace groundsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance of the 2-D point (rho, z), rho >= 0, to the profile of a cone
// frustum: radius r1 at z = -h, r2 at z = +h. The nearer of the flat cap
// and the slanted side, negative inside.
double frustumDistance(double rho, double z, double r1, double r2, double h) {
  // to the cap (bottom or top, whichever side z is on)
  const double cap_r = z < 0.0 ? r1 : r2;
  const double ax = rho - std::min(rho, cap_r), ay = std::abs(z) - h;
  // to the slanted side: segment from (r2, h) to (r1, -h)
  const double kx = r2 - r1, ky = 2.0 * h;
  const double t = std::clamp(((r2 - rho) * kx + (h - z) * ky) / (kx * kx + ky * ky), 0.0, 1.0);
  const double bx = rho - r2 + kx * t, by = z - h + ky * t;
  const bool inside = bx < 0.0 && ay < 0.0;
  const double d = std::sqrt(std::min(ax * ax + ay * ay, bx * bx + by * by));
  return inside ? -d : d;
}

double size(const Shape& s) { return std::max(s.bound(), 1e-9); }

void ring(std::vector<Vec3>& out, double r, double z, double spacing, int at_least) {
  if (!(r > 0.0)) {
    out.emplace_back(0.0, 0.0, z);
    return;
  }
  const int n = std::clamp(static_cast<int>(std::ceil(2.0 * kPi * r / spacing)), at_least, 64);
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    out.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
}

int segments(double length, double spacing) {
  return std::clamp(static_cast<int>(std::ceil(length / spacing - 1e-9)), 1, 64);
}

}  // namespace

double Shape::distance(const Vec3& p) const {
  switch (kind) {
    case ShapeKind::Box: {
      const double r = std::min(radius, half.minCoeff());
      const Vec3 q = p.cwiseAbs() - (half - Vec3::Constant(r));
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - r;
    }
    case ShapeKind::Sphere: return p.norm() - radius;
    case ShapeKind::Cylinder: {
      const double dx = std::hypot(p.x(), p.y()) - radius, dz = std::abs(p.z()) - half_height;
      return std::min(std::max(dx, dz), 0.0) + std::hypot(std::max(dx, 0.0), std::max(dz, 0.0));
    }
    case ShapeKind::Capsule: {
      const double z = std::clamp(p.z(), -half_height, half_height);
      return (p - Vec3(0.0, 0.0, z)).norm() - radius;
    }
    case ShapeKind::Cone: return frustumDistance(std::hypot(p.x(), p.y()), p.z(), radius, top_radius, half_height);
  }
  return 1.0;
}

namespace {

// The rounded box's gradient in closed form: outside its inner box (the
// box less the rounding), from the nearest point of the inner box; inside,
// along the axis (or axes, where they tie) of the nearest face. The same
// direction the central differences of distance() give, without their six
// evaluations.
Vec3 roundedBoxNormal(const Vec3& half, double radius, const Vec3& p) {
  const double r = std::min(radius, half.minCoeff());
  const Vec3 q = p.cwiseAbs() - (half - Vec3::Constant(r));
  Vec3 g = Vec3::Zero();
  if (q.maxCoeff() > 0.0) {
    for (int i = 0; i < 3; ++i)
      if (q[i] > 0.0) g[i] = p[i] > 0.0 ? q[i] : -q[i];
  } else {
    const double top = q.maxCoeff();
    for (int i = 0; i < 3; ++i)
      if (q[i] == top && p[i] != 0.0) g[i] = p[i] > 0.0 ? 1.0 : -1.0;
  }
  const double n = g.norm();
  return n > 0.0 ? Vec3(g / n) : Vec3::UnitZ();
}

}  // namespace

Vec3 Shape::normal(const Vec3& p) const {
  if (kind == ShapeKind::Box) return roundedBoxNormal(half, radius, p);
  const double e = 1e-6 * size(*this);
  Vec3 g;
  for (int i = 0; i < 3; ++i) {
    Vec3 a = p, b = p;
    a[i] += e;
    b[i] -= e;
    g[i] = distance(a) - distance(b);
  }
  const double n = g.norm();
  return n > 0.0 ? Vec3(g / n) : Vec3::UnitZ();
}

Vec3 Shape::extents() const {
  switch (kind) {
    case ShapeKind::Box: return half;
    case ShapeKind::Sphere: return Vec3::Constant(radius);
    case ShapeKind::Cylinder: return Vec3(radius, radius, half_height);
    case ShapeKind::Capsule: return Vec3(radius, radius, half_height + radius);
    case ShapeKind::Cone: {
      const double r = std::max(radius, top_radius);
      return Vec3(r, r, half_height);
    }
  }
  return Vec3::Zero();
}

double Shape::bound() const { return extents().norm(); }

double Shape::volume() const {
  switch (kind) {
    case ShapeKind::Box: return 8.0 * half.prod();
    case ShapeKind::Sphere: return 4.0 / 3.0 * kPi * radius * radius * radius;
    case ShapeKind::Cylinder: return 2.0 * kPi * radius * radius * half_height;
    case ShapeKind::Capsule:
      return 2.0 * kPi * radius * radius * half_height + 4.0 / 3.0 * kPi * radius * radius * radius;
    case ShapeKind::Cone: {
      const double a = radius, b = top_radius;
      return kPi * 2.0 * half_height / 3.0 * (a * a + a * b + b * b);
    }
  }
  return 0.0;
}

void Shape::massProperties(double m, Vec3* com, Mat3* inertia) const {
  *com = Vec3::Zero();
  Mat3& I = *inertia;
  I.setZero();
  switch (kind) {
    case ShapeKind::Box: {
      const Vec3 l = 2.0 * half;
      I.diagonal() << l.y() * l.y() + l.z() * l.z(), l.x() * l.x() + l.z() * l.z(), l.x() * l.x() + l.y() * l.y();
      I *= m / 12.0;
      return;
    }
    case ShapeKind::Sphere: I.diagonal().setConstant(0.4 * m * radius * radius); return;
    case ShapeKind::Cylinder: {
      const double r2 = radius * radius, l = 2.0 * half_height;
      I.diagonal() << m / 12.0 * (3.0 * r2 + l * l), m / 12.0 * (3.0 * r2 + l * l), 0.5 * m * r2;
      return;
    }
    case ShapeKind::Capsule: {
      // a cylinder and two hemispheres (centre of mass 3R/8 from the flat face)
      const double r = radius, h = half_height;
      const double vc = 2.0 * kPi * r * r * h, vs = 4.0 / 3.0 * kPi * r * r * r;
      const double mc = m * vc / (vc + vs), ms = m - mc;
      const double d = h + 3.0 * r / 8.0;
      const double perp = mc / 12.0 * (3.0 * r * r + 4.0 * h * h) + ms * (83.0 / 320.0 * r * r + d * d);
      I.diagonal() << perp, perp, (0.5 * mc + 0.4 * ms) * r * r;
      return;
    }
    case ShapeKind::Cone: {
      // by 400 disks: the centre of mass rises towards the smaller cap
      constexpr int n = 400;
      double mass = 0.0, mz = 0.0, izz = 0.0, ixx0 = 0.0, mzz = 0.0;
      for (int k = 0; k < n; ++k) {
        const double f = (k + 0.5) / n, z = -half_height + 2.0 * half_height * f;
        const double r = radius + (top_radius - radius) * f;
        const double dm = r * r;  // proportional to the disk's mass
        mass += dm;
        mz += dm * z;
        mzz += dm * z * z;
        izz += 0.5 * dm * r * r;
        ixx0 += 0.25 * dm * r * r;
      }
      const double zc = mz / mass, s = m / mass;
      *com = Vec3(0.0, 0.0, zc);
      const double perp = s * (ixx0 + mzz - mass * zc * zc);
      I.diagonal() << perp, perp, s * izz;
      return;
    }
  }
}

std::vector<Vec3> Shape::probes(double spacing) const {
  spacing = std::max(spacing, 1e-3 * size(*this));
  std::vector<Vec3> out;
  switch (kind) {
    case ShapeKind::Box: {
      const double r = std::min(radius, half.minCoeff());
      const Vec3 e = half - Vec3::Constant(r);
      // corners
      for (int c = 0; c < 8; ++c) {
        const Vec3 s((c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0);
        out.push_back(s.cwiseProduct(e) + r * s.normalized());
      }
      // inside of the 12 edges: along axis a, at the signs of the other two
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const int n = segments(2.0 * half[a], spacing);
        for (int sb = -1; sb <= 1; sb += 2)
          for (int sc = -1; sc <= 1; sc += 2)
            for (int k = 1; k < n; ++k) {
              Vec3 p = Vec3::Zero(), dir = Vec3::Zero();
              p[a] = -e[a] + 2.0 * e[a] * k / n;
              p[b] = sb * e[b];
              p[c] = sc * e[c];
              dir[b] = sb;
              dir[c] = sc;
              out.push_back(p + r * dir.normalized());
            }
      }
      return out;
    }
    case ShapeKind::Sphere: {
      const int n = std::clamp(static_cast<int>(std::ceil(4.0 * kPi * radius * radius / (spacing * spacing))), 14, 400);
      const double golden = kPi * (3.0 - std::sqrt(5.0));
      for (int k = 0; k < n; ++k) {
        const double z = 1.0 - 2.0 * (k + 0.5) / n, r = std::sqrt(1.0 - z * z);
        out.push_back(radius * Vec3(r * std::cos(golden * k), r * std::sin(golden * k), z));
      }
      return out;
    }
    case ShapeKind::Cylinder: {
      const int n = segments(2.0 * half_height, spacing);
      for (int k = 0; k <= n; ++k) ring(out, radius, -half_height + 2.0 * half_height * k / n, spacing, 8);
      out.emplace_back(0.0, 0.0, half_height);
      out.emplace_back(0.0, 0.0, -half_height);
      return out;
    }
    case ShapeKind::Capsule: {
      const int n = segments(2.0 * half_height, spacing);
      for (int k = 0; k <= n; ++k) ring(out, radius, -half_height + 2.0 * half_height * k / n, spacing, 8);
      const double c = std::sqrt(0.5);
      ring(out, c * radius, half_height + c * radius, spacing, 6);
      ring(out, c * radius, -half_height - c * radius, spacing, 6);
      out.emplace_back(0.0, 0.0, half_height + radius);
      out.emplace_back(0.0, 0.0, -half_height - radius);
      return out;
    }
    case ShapeKind::Cone: {
      const int n = segments(std::hypot(2.0 * half_height, radius - top_radius), spacing);
      for (int k = 0; k <= n; ++k) {
        const double f = static_cast<double>(k) / n;
        ring(out, radius + (top_radius - radius) * f, -half_height + 2.0 * half_height * f, spacing, 8);
      }
      out.emplace_back(0.0, 0.0, -half_height);
      return out;
    }
  }
  return out;
}

}  // namespace groundsim
