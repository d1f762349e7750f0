#include "physics/ground/ground.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace groundsim {

bool groundPointBelow(GroundProbe& g, double x, double y, Vec3* point, Vec3* normal) {
  // Newton on z, from z = 0, guarded by bisection once a bracket is known
  double z = 0.0, lo = -1e9, hi = 1e9;
  Vec3 grad;
  for (int it = 0; it < 200; ++it) {
    const double H = g.eval(Vec3(x, y, z), &grad);
    if (std::abs(H) < 1e-12) break;
    if (H > 0) hi = std::min(hi, z); else lo = std::max(lo, z);
    double zn = (std::abs(grad.z()) > 1e-12) ? z - H / grad.z() : z - H;
    if (!(zn > lo && zn < hi)) zn = (lo > -1e9 && hi < 1e9) ? 0.5 * (lo + hi) : z - H;
    z = zn;
  }
  const double H = g.eval(Vec3(x, y, z), &grad);
  if (!(std::abs(H) < 1e-6) || !(grad.norm() > 0)) return false;
  *point = Vec3(x, y, z);
  *normal = grad.normalized();
  return true;
}

bool groundPointBelow(const Ground& g, double x, double y, Vec3* point, Vec3* normal) {
  GroundProbe probe(g);
  return groundPointBelow(probe, x, y, point, normal);
}

void Ground::heights(const double* x, const double* y, const double* z, int begin, int end,
                     double* H) const {
  Vec3 g;
  for (int k = begin; k < end; ++k) H[k] = eval(Vec3(x[k], y[k], z[k]), &g);
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

class Plane final : public Ground {
 public:
  Plane(const Vec3& n, double offset) : n_(n.normalized()), offset_(offset) {}
  double eval(const Vec3& p, Vec3* grad) const override {
    *grad = n_;
    return n_.dot(p) - offset_;
  }
  void heights(const double* x, const double* y, const double* z, int begin, int end,
               double* H) const override {
    const double a = n_.x(), b = n_.y(), c = n_.z(), d = offset_;
    for (int k = begin; k < end; ++k) H[k] = a * x[k] + b * y[k] + c * z[k] - d;
  }
  double gradientBound() const override { return 1.0; }
  bool asPlane(Vec3* n, double* offset) const override {
    *n = n_;
    *offset = offset_;
    return true;
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "plane n=(" << n_.x() << "," << n_.y() << "," << n_.z() << ") offset=" << offset_;
    return s.str();
  }

 private:
  Vec3 n_;
  double offset_;
};

class CosineWave final : public Ground {
 public:
  CosineWave(double a, double wl) : a_(a), k_(kTwoPi / wl) {}
  double eval(const Vec3& p, Vec3* grad) const override {
    const double kx = k_ * p.x();
    *grad = Vec3(a_ * k_ * std::sin(kx), 0.0, 1.0);
    return p.z() - a_ * std::cos(kx);
  }
  double gradientBound() const override { return std::hypot(1.0, a_ * k_); }
  std::string describe() const override {
    std::ostringstream s;
    s << "cosine wave amplitude=" << a_ << " wavelength=" << kTwoPi / k_;
    return s.str();
  }

 private:
  double a_, k_;
};

class Parabola final : public Ground {
 public:
  explicit Parabola(double c) : c_(c) {}
  double eval(const Vec3& p, Vec3* grad) const override {
    *grad = Vec3(-c_ * p.x(), -c_ * p.y(), 1.0);
    return p.z() - 0.5 * c_ * (p.x() * p.x() + p.y() * p.y());
  }
  // unbounded gradient far from the axis: no global bound
  std::string describe() const override {
    std::ostringstream s;
    s << "parabola curvature=" << c_;
    return s.str();
  }

 private:
  double c_;
};

class Cone final : public Ground {
 public:
  explicit Cone(double slope) : s_(slope) {}
  double eval(const Vec3& p, Vec3* grad) const override {
    const double rho = std::hypot(p.x(), p.y());
    // the apex has no gradient; any unit-slope direction is a valid
    // subgradient, and returning the vertical keeps the normal defined
    if (rho < 1e-12) {
      *grad = Vec3(0.0, 0.0, 1.0);
    } else {
      *grad = Vec3(-s_ * p.x() / rho, -s_ * p.y() / rho, 1.0);
    }
    return p.z() - s_ * rho;
  }
  double gradientBound() const override { return std::hypot(1.0, s_); }
  std::string describe() const override {
    std::ostringstream s;
    s << "cone slope=" << s_;
    return s.str();
  }

 private:
  double s_;
};

class SinSinBumps final : public Ground {
 public:
  SinSinBumps(double a, double wx, double wy) : a_(a), kx_(kTwoPi / wx), ky_(kTwoPi / wy) {}
  double eval(const Vec3& p, Vec3* grad) const override {
    const double sx = std::sin(kx_ * p.x()), cx = std::cos(kx_ * p.x());
    const double sy = std::sin(ky_ * p.y()), cy = std::cos(ky_ * p.y());
    *grad = Vec3(-a_ * kx_ * cx * sy, -a_ * ky_ * sx * cy, 1.0);
    return p.z() - a_ * sx * sy;
  }
  double gradientBound() const override {
    return std::sqrt(1.0 + a_ * a_ * (kx_ * kx_ + ky_ * ky_));
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "sin-sin bumps amplitude=" << a_ << " wavelengths=(" << kTwoPi / kx_ << ","
      << kTwoPi / ky_ << ")";
    return s.str();
  }

 private:
  double a_, kx_, ky_;
};

}  // namespace

GroundPtr makePlane(const Vec3& normal, double offset) {
  return std::make_shared<Plane>(normal, offset);
}

GroundPtr makeIncline(double angle_rad, const Vec3& downhill) {
  Vec3 d(downhill.x(), downhill.y(), 0.0);
  d.normalize();
  // the surface z = -tan(angle) * (d . p): normal (sin a d + cos a z)
  const Vec3 n = std::sin(angle_rad) * d + std::cos(angle_rad) * Vec3::UnitZ();
  return makePlane(n, 0.0);
}

GroundPtr makeCosineWave(double amplitude, double wavelength) {
  return std::make_shared<CosineWave>(amplitude, wavelength);
}
GroundPtr makeParabola(double curvature) { return std::make_shared<Parabola>(curvature); }
GroundPtr makeCone(double slope) { return std::make_shared<Cone>(slope); }
GroundPtr makeSinSinBumps(double amplitude, double wavelength_x, double wavelength_y) {
  return std::make_shared<SinSinBumps>(amplitude, wavelength_x, wavelength_y);
}

}  // namespace groundsim
