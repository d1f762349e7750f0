// Rigid bodies of mass points: inertia from the points, torque-free motion.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/checks/diagnostics.hpp"
#include "support/scenes.hpp"

using namespace groundsim;
using namespace groundsim::test;

namespace {

BodySpec box(double a, double b, double c, double m) {
  BodySpec s;
  s.name = "box";
  for (int i = 0; i < 8; ++i) {
    s.points.push_back(Vec3(i & 1 ? a : -a, i & 2 ? b : -b, i & 4 ? c : -c));
    s.masses.push_back(m / 8);
    s.contact.push_back(false);
  }
  return s;
}

}  // namespace

TEST(Inertia, RingOfPointsIsAThinHoop) {
  ModelBuilder b(spaceOptions(1e-3), farGround());
  b.addBody(hoop(20, 1.5, 0.4));
  const Mat3 I = b.model().bodies[0].inertia;
  const double mr2 = 0.4 * 1.5 * 1.5;
  EXPECT_NEAR(I(1, 1), mr2, 1e-12);        // about the axle
  EXPECT_NEAR(I(0, 0), mr2 / 2, 1e-12);    // about a diameter
  EXPECT_NEAR(I(2, 2), mr2 / 2, 1e-12);
  EXPECT_NEAR((I - Mat3(I.diagonal().asDiagonal())).norm(), 0.0, 1e-12);
}

TEST(Inertia, BoxCornersAndCentreOfMass) {
  ModelBuilder b(spaceOptions(1e-3), farGround());
  BodySpec s = box(1.0, 0.5, 0.25, 8.0);
  s.origin = Vec3(3, 4, 5);
  s.points.push_back(Vec3(2, 0, 0));  // an extra mass moves the centre
  s.masses.push_back(2.0);
  s.contact.push_back(false);
  b.addBody(s);
  auto built = b.build();
  EXPECT_NEAR(built.model->bodies[0].mass, 10.0, 1e-12);
  // centre of mass (eq. 4): (8 * 0 + 2 * 2) / 10 = 0.4 along x
  EXPECT_LT((bodyPos(built.initial.y, 0) - Vec3(3.4, 4, 5)).norm(), 1e-12);
  // parallel axis: the corners about x' = 0.4 plus the extra point
  const Mat3 I = built.model->bodies[0].inertia;
  EXPECT_NEAR(I(0, 0), 8.0 * (0.25 + 0.0625), 1e-12);
  EXPECT_NEAR(I(1, 1), 8.0 * (1.0 + 0.0625) + 8.0 * 0.16 + 2.0 * 1.6 * 1.6, 1e-12);
}

TEST(Inertia, CollinearPointsAreRejected) {
  ModelBuilder b(spaceOptions(1e-3), farGround());
  BodySpec s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  s.masses = {1, 1, 1};
  s.contact = {false, false, false};
  EXPECT_THROW(b.addBody(s), std::invalid_argument);
}

TEST(Inertia, WorldTensorRotatesWithTheBody) {
  // a box turned 90 degrees about z, spun about world x: its long axis now
  // lies along y, so I_world(0,0) is the body's I(1,1)
  ModelBuilder b(spaceOptions(1e-3), farGround());
  BodySpec s = box(2.0, 0.5, 0.25, 8.0);
  s.orientation = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  s.angular_velocity = Vec3(1.0, 0, 0);
  b.addBody(s);
  auto built = b.build();
  const Mat3 Ib = built.model->bodies[0].inertia;
  EXPECT_NEAR(bodyMom(built.initial.y, 0).x(), Ib(1, 1), 1e-12);
  EXPECT_LT((angularVelocity(*built.model, built.initial, 0) - Vec3(1, 0, 0)).norm(), 1e-12);
}

TEST(FreeRigidBody, SymmetricTopPrecessesAtTheAnalyticRate) {
  // Torque-free symmetric top (a hoop: I1 = I2 = m r^2 / 2 about diameters,
  // I3 = m r^2 about the axle y). The axle sweeps a cone about the fixed
  // angular momentum L at the rate |L| / I1, keeping its angle to L.
  const double h = 1e-4;
  ModelBuilder b(spaceOptions(h), farGround());
  BodySpec s = hoop(24, 1.0, 1.0);
  s.angular_velocity = Vec3(0.7, 3.0, 0.0);
  b.addBody(s);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  const double I1 = 0.5;
  const Vec3 L = bodyMom(sim.state().y, 0);
  const Vec3 Lhat = L.normalized();
  const Vec3 axis0 = Vec3::UnitY();
  const double cone = std::acos(axis0.dot(Lhat));
  const double e0 = sim.energy().total();
  const double T = 2.0;
  ASSERT_TRUE(sim.step(static_cast<long long>(T / h)));
  const Vec3 axis = Quat(bodyRot(sim.state().y, 0)) * Vec3::UnitY();
  EXPECT_NEAR(std::acos(axis.dot(Lhat)), cone, 1e-6);
  // precession angle about L, from the projections onto the plane normal to L
  const Vec3 p0 = (axis0 - axis0.dot(Lhat) * Lhat).normalized();
  const Vec3 p1 = (axis - axis.dot(Lhat) * Lhat).normalized();
  double angle = std::atan2(Lhat.dot(p0.cross(p1)), p0.dot(p1));
  const double expected = std::remainder(L.norm() / I1 * T, 2 * kPi);
  EXPECT_NEAR(std::remainder(angle - expected, 2 * kPi), 0.0, 1e-3);
  EXPECT_LT((bodyMom(sim.state().y, 0) - L).norm(), 1e-12);  // exactly, no torque
  EXPECT_NEAR(sim.energy().total(), e0, 1e-4 * e0);
}

TEST(FreeRigidBody, SpinNearTheIntermediateAxisKeepsEnergyAndMomentum) {
  ModelBuilder b(spaceOptions(1e-3), farGround());
  BodySpec s = box(1.0, 0.6, 0.3, 3.0);
  s.angular_velocity = Vec3(0.01, 4.0, 0.01);  // intermediate axis: it tumbles
  b.addBody(s);
  auto built = b.build();
  Simulator sim(built.model, built.initial);
  const Vec3 L0 = bodyMom(sim.state().y, 0);
  const double e0 = sim.energy().total();
  double emax = e0, emin = e0, lowest_alignment = 1.0;
  for (int i = 0; i < 200; ++i) {  // 20 s
    sim.step(100);
    const double e = sim.energy().total();
    emax = std::max(emax, e);
    emin = std::min(emin, e);
    const Vec3 axis = Quat(bodyRot(sim.state().y, 0)) * Vec3::UnitY();
    lowest_alignment = std::min(lowest_alignment, axis.dot(Vec3::UnitY()));
  }
  EXPECT_LT((bodyMom(sim.state().y, 0) - L0).norm(), 1e-12 * L0.norm() + 1e-12);
  EXPECT_LT((emax - emin) / e0, 0.02);
  // it did tumble: spin about the intermediate axis is unstable, so the
  // body's y axis turned over at some point (Dzhanibekov effect)
  EXPECT_LT(lowest_alignment, -0.5);
  EXPECT_TRUE(sim.healthy());
}
