// Every ground the scenario layer builds returns a gradient that matches
// finite differences of its own H; the expression ground's numerical
// gradient matches the analytic gradient of the same surface.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "scenario/expression_ground.hpp"
#include "scenario/ground_spec.hpp"
#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

// Reference derivative of H alone: 6th-order central differences with a
// step of ~1e-3 (independent of the ground's own gradient code).
Vec3 referenceGradient(const Ground& g, const Vec3& p) {
  Vec3 out, unused;
  for (int a = 0; a < 3; ++a) {
    const double h = 1e-3 * std::max(1.0, std::abs(p[a]));
    auto H = [&](double k) {
      Vec3 q = p;
      q[a] += k * h;
      return g.eval(q, &unused);
    };
    out[a] = (45.0 * (H(1) - H(-1)) - 9.0 * (H(2) - H(-2)) + (H(3) - H(-3))) / (60.0 * h);
  }
  return out;
}

GroundSpec specOf(const std::string& json) {
  auto d = minimalDoc();
  d["ground"] = nlohmann::json::parse(json);
  return parseScenario(d).ground;
}

class EveryGround : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryGround, GradientMatchesFiniteDifferences) {
  const GroundPtr g = makeGround(specOf(GetParam()));
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p(u(rng), u(rng), 0.2 * u(rng));
    if (std::hypot(p.x(), p.y()) < 0.1) continue;  // the cone's apex has no gradient
    Vec3 grad;
    g->eval(p, &grad);
    const Vec3 ref = referenceGradient(*g, p);
    EXPECT_LE((grad - ref).norm(), 1e-6 * std::max(1.0, ref.norm()))
        << g->describe() << " at " << p.transpose() << ": " << grad.transpose() << " vs " << ref.transpose();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenario, EveryGround,
    ::testing::Values(R"({"type": "plane", "normal": [0.1, -0.2, 1], "offset": 0.3})",
                      R"({"type": "incline", "angle_deg": 30, "downhill": [1, 1]})",
                      R"({"type": "cosine", "amplitude": 0.5})",
                      R"({"type": "parabola", "curvature": 0.3})",
                      R"({"type": "cone", "slope": -0.4})",
                      R"({"type": "bumps", "amplitude": 0.2, "wavelength_x": 5, "wavelength_y": 7})",
                      R"({"type": "expression", "expression": "z - 0.3*sin(x)*cos(0.5*y) + 0.01*x*y"})"));

TEST(ExpressionGradient, MatchesTheAnalyticCosineTo1e8) {
  // the report's z - 0.5 cos x: grad = (0.5 sin x, 0, 1)
  const ExpressionGround g("z - 0.5*cos(x)");
  for (double x : {0.0, 0.3, 1.0, std::numbers::pi / 2, 3.0, -7.5, 40.0, 1000.0, -12345.678})
    for (double z : {0.0, -0.4, 2.0}) {
      const Vec3 p(x, 0.7 * x, z);
      Vec3 grad;
      const double H = g.eval(p, &grad);
      const Vec3 exact(0.5 * std::sin(x), 0.0, 1.0);
      EXPECT_LE((grad - exact).norm(), 1e-8 * exact.norm()) << "x = " << x << ": " << grad.transpose();
      EXPECT_NEAR(H, z - 0.5 * std::cos(x), 1e-14 * std::max(1.0, std::abs(x)));
    }
}

TEST(ExpressionGradient, AgreesWithTheBuiltInCosineGround) {
  const ExpressionGround expr("z - 0.5*cos(x)");
  const GroundPtr exact = makeCosineWave(0.5, 2.0 * std::numbers::pi);
  for (double x = -20.0; x <= 20.0; x += 0.37) {
    const Vec3 p(x, 1.0, 0.1);
    Vec3 ge, gx;
    EXPECT_NEAR(expr.eval(p, &ge), exact->eval(p, &gx), 1e-12);
    EXPECT_LE((ge - gx).norm(), 1e-8 * gx.norm());
  }
}

}  // namespace
}  // namespace groundsim::scenario::test
