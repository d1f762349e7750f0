// Friction by place: a sliding point mass stops at v^2 / (2 mu g) of the
// patch it slides on, and across a border at the distance both zones give.
#include <gtest/gtest.h>

#include "physics/build/model_builder.hpp"
#include "physics/simulator.hpp"
#include "physics/ground/surface_friction.hpp"
#include "scenario/expression_ground.hpp"

using namespace groundsim;

namespace {

FrictionPatch rect(double x0, double y0, double x1, double y1, double mu) {
  FrictionPatch p;
  p.x0 = x0;
  p.y0 = y0;
  p.x1 = x1;
  p.y1 = y1;
  p.mu = mu;
  return p;
}

// Distance a point mass slides from x = 0 at 5 m/s on z = 0 until it stops.
double skid(GroundPtr ground, double scene_mu, FrictionModel model = FrictionModel::StickSlip,
            IntegratorKind integrator = IntegratorKind::SemiImplicitEuler, bool damped = true) {
  Options o;
  o.contact.friction_model = model;
  o.integrator = integrator;
  o.dt = 1e-4;
  o.contact.stiffness = 1e5;
  o.contact.damping = damped ? 2.0 * std::sqrt(1e5 * 1.0) : 0.0;
  o.contact.friction = scene_mu;
  ModelBuilder b(o, std::move(ground));
  b.addParticle(1.0, Vec3(0, 0, -9.8 / 1e5), Vec3(5.0, 0, 0));  // resting at its static sag
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  while (sim.state().y[3] > 0 && sim.state().t < 20) sim.step();
  return sim.state().y[0];
}

}  // namespace

TEST(FrictionPatches, SkidStopsAtVSquaredOverTwoMuGOfThePatch) {
  const GroundPtr plane = makePlane(Vec3::UnitZ(), 0);
  const double g = 9.8, v2 = 25.0;
  EXPECT_NEAR(skid(plane, 0.5), v2 / (2 * 0.5 * g), 0.01 * v2 / (2 * 0.5 * g));
  // an ice patch under the whole slide: the scene's 0.5 no longer counts
  const GroundPtr ice = withSurfaceFriction(plane, {rect(-10, -10, 100, 10, 0.1)});
  EXPECT_NEAR(skid(ice, 0.5), v2 / (2 * 0.1 * g), 0.01 * v2 / (2 * 0.1 * g));
  // a patch elsewhere changes nothing
  FrictionPatch far;
  far.shape = FrictionPatch::Shape::Circle;
  far.cx = 0;
  far.cy = 50;
  far.radius = 5;
  far.mu = 0.05;
  EXPECT_NEAR(skid(withSurfaceFriction(plane, {far}), 0.5), skid(plane, 0.5), 1e-12);
  // the explicit (report's sign) friction reads the patch's mu too
  EXPECT_NEAR(skid(ice, 0.5, FrictionModel::Sign), v2 / (2 * 0.1 * g), 0.01 * v2 / (2 * 0.1 * g));
}

// A scene without friction or damping of its own is velocity independent
// for Verlet's force cache, unless a patch gives its contacts friction: the
// cache must ask each contact's mu, not the scene's contact.friction.
TEST(FrictionPatches, GripOnAFrictionlessSceneCountsForVerletsForceCache) {
  const double g = 9.8, v2 = 25.0, mu = 0.5;
  const GroundPtr grip = withSurfaceFriction(makePlane(Vec3::UnitZ(), 0), {rect(-10, -10, 100, 10, mu)});
  const double d = skid(grip, 0.0, FrictionModel::StickSlip, IntegratorKind::VelocityVerlet, false);
  EXPECT_NEAR(d, v2 / (2 * mu * g), 0.01 * v2 / (2 * mu * g));
}

TEST(FrictionPatches, CrossingFromAsphaltOntoIceStopsWhereBothZonesSay) {
  // mu 1 for x < 0.5 m, then ice (0.1): v1^2 = v^2 - 2 mu1 g a, then
  // d = a + v1^2 / (2 mu2 g)
  const GroundPtr plane = makePlane(Vec3::UnitZ(), 0);
  const double a = 0.5, g = 9.8;
  // the later patch wins where they overlap
  const GroundPtr road = withSurfaceFriction(plane, {rect(-10, -10, 100, 10, 0.1), rect(-10, -10, a, 10, 1.0)});
  const double expected = a + (25.0 - 2 * 1.0 * g * a) / (2 * 0.1 * g);
  EXPECT_NEAR(skid(road, 0.7), expected, 0.01 * expected);
}

TEST(FrictionMap, BilinearInsideAndTheSceneFrictionOutside) {
  auto map = std::make_shared<FrictionGrid>();
  map->nx = 2;
  map->ny = 2;
  map->cell = 10;
  map->mu = {0.2f, 0.4f, 0.6f, 0.8f};
  const GroundPtr g = withSurfaceFriction(makePlane(Vec3::UnitZ(), 0), {}, map);
  EXPECT_NEAR(g->friction(Vec3(0, 0, 0), 0.9), 0.2, 1e-7);
  EXPECT_NEAR(g->friction(Vec3(5, 0, 0), 0.9), 0.3, 1e-7);
  EXPECT_NEAR(g->friction(Vec3(5, 5, 0), 0.9), 0.5, 1e-7);
  EXPECT_NEAR(g->friction(Vec3(11, 5, 0), 0.9), 0.9, 1e-12);  // off the map
  // a patch over the map wins
  const GroundPtr h = withSurfaceFriction(makePlane(Vec3::UnitZ(), 0), {rect(4, 4, 6, 6, 0.05)}, map);
  EXPECT_NEAR(h->friction(Vec3(5, 5, 0), 0.9), 0.05, 1e-12);
  // no patches, no map: the ground itself, unwrapped
  const GroundPtr plane = makePlane(Vec3::UnitZ(), 0);
  EXPECT_EQ(withSurfaceFriction(plane, {}).get(), plane.get());
}

TEST(FrictionPatches, AWrappedGroundKeepsItsShapeAndItsEvaluator) {
  // a ground with evaluation state (a parsed expression) under patches: the
  // simulation must get the wrapped ground's evaluator, not the const path
  const auto expr = std::make_shared<scenario::ExpressionGround>("z - 0.5*cos(x)");
  const GroundPtr wrapped = withSurfaceFriction(expr, {rect(0, 0, 1, 1, 0.2)});
  ASSERT_NE(wrapped.get(), expr.get());
  EXPECT_NE(wrapped->makeEvaluator(), nullptr);
  GroundProbe a(*wrapped), b(*expr);
  Vec3 ga, gb;
  for (double x = -3; x < 3; x += 0.37) {
    const Vec3 p(x, 0.5, 0.1);
    EXPECT_EQ(a.eval(p, &ga), b.eval(p, &gb));
    EXPECT_EQ(ga, gb);
  }
  EXPECT_EQ(wrapped->gradientBound(), expr->gradientBound());
}
