// Collision shapes: signed distances, normals, mass properties and probes
// against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "physics/collision/shape.hpp"

namespace groundsim {
namespace {

constexpr double kPi = std::numbers::pi;

Shape box(double x, double y, double z, double round = 0.0) {
  Shape s;
  s.kind = ShapeKind::Box;
  s.half = Vec3(x, y, z);
  s.radius = round;
  return s;
}

TEST(Shape, BoxDistanceInsideOutsideAndAtCorners) {
  const Shape s = box(1.0, 0.5, 0.25);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(2.0, 0, 0)), 1.0);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0.9, 0, 0)), -0.1);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0, 0, 0)), -0.25);  // nearest face: z
  EXPECT_NEAR(s.distance(Vec3(2.0, 1.5, 0.25)), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR((s.normal(Vec3(0.9, 0.1, 0.0)) - Vec3::UnitX()).norm(), 0.0, 1e-6);
  // rounding keeps the extents and rounds the corner
  const Shape r = box(1.0, 1.0, 1.0, 0.2);
  EXPECT_NEAR(r.distance(Vec3(1.0, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(r.distance(Vec3(1.0, 1.0, 1.0)), std::sqrt(3.0) * 0.2 - 0.2, 1e-12);
}

// The box's normal is the gradient of its distance, in closed form: it
// agrees with central differences of distance() everywhere off the medial
// planes (where the gradient jumps), outside, inside and in the rounding.
TEST(Shape, BoxNormalIsTheGradientOfTheDistance) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const Shape s = box(1.0, 0.6, 0.3, 0.12);
  int checked = 0;
  for (int t = 0; t < 2000; ++t) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double e = 1e-7;
    Vec3 g;
    for (int i = 0; i < 3; ++i) {
      Vec3 a = p, b = p;
      a[i] += e;
      b[i] -= e;
      g[i] = (s.distance(a) - s.distance(b)) / (2.0 * e);
    }
    // a point within 1e-5 of a tie of faces has no single gradient
    if (std::abs(g.norm() - 1.0) > 1e-6) continue;
    EXPECT_NEAR((s.normal(p) - g).norm(), 0.0, 1e-6) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 1900);
}

TEST(Shape, RoundKindsDistances) {
  Shape s;
  s.kind = ShapeKind::Sphere;
  s.radius = 0.5;
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0, 0, 2)), 1.5);
  s.kind = ShapeKind::Cylinder;
  s.radius = 1.0;
  s.half_height = 2.0;
  EXPECT_DOUBLE_EQ(s.distance(Vec3(3, 0, 0)), 2.0);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0, 0, -3)), 1.0);
  EXPECT_NEAR(s.distance(Vec3(0.5, 0, 1.9)), -0.1, 1e-12);
  EXPECT_NEAR(s.distance(Vec3(4, 0, 6)), 5.0, 1e-12);  // to the rim edge (3, 4)
  s.kind = ShapeKind::Capsule;
  s.radius = 0.5;
  s.half_height = 1.0;
  EXPECT_DOUBLE_EQ(s.distance(Vec3(0, 0, 2.5)), 1.0);
  EXPECT_DOUBLE_EQ(s.distance(Vec3(1.5, 0, 0.3)), 1.0);
  // a pointed cone, base radius 1 at z = -1, apex at z = +1
  s.kind = ShapeKind::Cone;
  s.radius = 1.0;
  s.top_radius = 0.0;
  s.half_height = 1.0;
  EXPECT_NEAR(s.distance(Vec3(0, 0, 2)), 1.0, 1e-12);
  EXPECT_NEAR(s.distance(Vec3(0, 0, -2)), 1.0, 1e-12);
  EXPECT_LT(s.distance(Vec3(0.2, 0, -0.5)), 0.0);
  // on the slanted side's outward normal, (2, 1) / sqrt 5, 1 m out
  const Vec3 mid(0.5, 0.0, 0.0), out = Vec3(2.0, 0.0, 1.0).normalized();
  EXPECT_NEAR(s.distance(mid + out), 1.0, 1e-12);
  EXPECT_NEAR((s.normal(mid + 0.1 * out) - out).norm(), 0.0, 1e-6);
}

TEST(Shape, MassPropertiesMatchClosedForms) {
  Vec3 c;
  Mat3 I;
  box(1.0, 0.5, 0.25).massProperties(12.0, &c, &I);
  EXPECT_NEAR(I(0, 0), 1.0 * (1.0 + 0.25), 1e-12);  // m/12 (b^2 + c^2), b = 1, c = 0.5
  EXPECT_NEAR(I(2, 2), 1.0 * (4.0 + 1.0), 1e-12);
  Shape cone;
  cone.kind = ShapeKind::Cone;
  cone.radius = 0.3;
  cone.half_height = 0.5;
  cone.massProperties(2.0, &c, &I);
  // solid cone: centre of mass h/4 above the base, I_axis = 3/10 m r^2,
  // I_perp = 3/20 m r^2 + 3/80 m h^2 about it
  const double h = 1.0, r = 0.3, m = 2.0;
  EXPECT_NEAR(c.z(), -0.5 + h / 4.0, 1e-5);
  EXPECT_NEAR(I(2, 2), 0.3 * m * r * r, 1e-4 * 0.3 * m * r * r);
  EXPECT_NEAR(I(0, 0), 3.0 / 20.0 * m * r * r + 3.0 / 80.0 * m * h * h, 1e-4);
  EXPECT_NEAR(cone.volume(), kPi * r * r * h / 3.0, 1e-12);
}

TEST(Shape, ProbesLieOnTheSurfaceWithinTheSpacing) {
  Shape kinds[5];
  kinds[0] = box(2.0, 0.9, 0.7, 0.05);
  kinds[1].kind = ShapeKind::Sphere;
  kinds[2].kind = ShapeKind::Cylinder;
  kinds[3].kind = ShapeKind::Capsule;
  kinds[4].kind = ShapeKind::Cone;
  kinds[4].top_radius = 0.1;
  for (const Shape& s : kinds) {
    const auto probes = s.probes(0.3);
    ASSERT_GE(probes.size(), 8u);
    for (const Vec3& p : probes) EXPECT_NEAR(s.distance(p), 0.0, 1e-9) << static_cast<int>(s.kind);
  }
  // a box's edges are sampled no farther apart than the spacing
  const auto probes = box(2.0, 0.9, 0.7).probes(0.3);
  int on_long_edge = 0;
  for (const Vec3& p : probes) on_long_edge += std::abs(p.y() - 0.9) < 1e-12 && std::abs(p.z() - 0.7) < 1e-12;
  EXPECT_GE(on_long_edge, static_cast<int>(std::ceil(4.0 / 0.3)) + 1);
}

}  // namespace
}  // namespace groundsim
