// The rigid stick-slip tyre (`tyres.model: "stick_slip"`) against closed
// forms, on the sedan and the front-driven hatchback: a friction circle of
// mu_static N at each patch while it sticks, mu_sliding N opposite the
// slip when it slides; no slip angle, no slip ratio below the limit.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "physics/integrators/integrator.hpp"
#include "physics/ground/surface_friction.hpp"
#include "physics/road_car/tyre_stick_slip.hpp"
#include "scenario/scenario.hpp"
#include "scenario/scenario_error.hpp"
#include "sedan.hpp"

namespace groundsim::test {
namespace {

RoadCarParams stickSlip(RoadCarParams p) {
  for (auto& t : p.tyre) t.slip_model = false;
  return p;
}

class StickSlipTyreTest : public ::testing::TestWithParam<Car> {
 protected:
  RoadCarParams P() const { return stickSlip(GetParam().p); }
  double muStatic(double mu_ground = 1.0) const { return mu_ground * P().tyre[0].friction_scale; }
  double muSliding(double mu_ground = 1.0) const { return muStatic(mu_ground) * P().tyre[0].sliding_ratio; }
  double dragC() const { return 0.5 * P().aero.air_density * P().aero.drag_area; }  // N s^2 / m^2
  // distance to stop from v0 under a constant force F0 plus drag c v^2 with
  // effective (translating plus spinning) mass me: (me / 2c) ln(1 + c v0^2 / F0)
  double stopDistance(double v0, double F0, double me) const {
    return me / (2.0 * dragC()) * std::log(1.0 + dragC() * v0 * v0 / F0);
  }
};

// Parked on a 20% grade with the handbrake: the rear patches stick and the
// brakes hold the wheels, so once the ride motion has died away nothing
// moves. The solve leaves a relative residual of 1e-10 of the holding
// impulse (~6 N s per step): ~1e-12 m/s, so under 1e-8 m in a minute.
// (The Magic Formula tyre's deflection springs creep ~1e-6 m an hour.)
TEST_P(StickSlipTyreTest, ParkedOnATwentyPercentGradeDoesNotCreep) {
  const GroundPtr hill = makeIncline(std::atan(0.2), Vec3::UnitX());
  for (double yaw : {0.0, kPi}) {  // nose downhill, nose uphill
    CarSim cs = makeCar(P(), carOptions(), 0.0, hill, yaw);
    CarControls c;
    c.handbrake = true;
    cs.set(c);
    ASSERT_TRUE(cs.runUntil(10.0));  // ride motion: decay rate > 2.4/s, e^-24 left
    const Vec3 x1 = cs.pos();
    ASSERT_TRUE(cs.runUntil(70.0));
    EXPECT_LT((cs.pos() - x1).norm(), 1e-8) << "yaw " << yaw;
    for (int w = 2; w < 4; ++w) EXPECT_NEAR(cs.sample().wheels[w].spin, 0.0, 1e-9);

    CarSim free_car = makeCar(P(), carOptions(), 0.0, hill, yaw);
    ASSERT_TRUE(free_car.runUntil(3.0));
    // rolling freely, it accelerates at g sin(theta) / (1 + 4 I / (m r^2))
    // less rolling resistance: over 2 m/s after 3 s
    EXPECT_GT(free_car.vel().norm(), 2.0) << "without the handbrake it rolls";
  }
}

// ABS off, brake 1 from 100 km/h: every wheel locks (the sedan's rear
// brakes only once the pitch has moved load forward) and the car slides at mu_sliding (m g in total whatever the load transfer:
// the friction is linear in N), against drag, straight.
TEST_P(StickSlipTyreTest, LockedWheelsStopInTheSlidingFrictionDistance) {
  RoadCarParams p = P();
  p.brakes.abs = false;
  const double v0 = 100.0 / 3.6;
  CarSim cs = brakingCar(p, carOptions(), v0);
  const Vec3 x0 = cs.pos();
  ASSERT_TRUE(cs.runUntil(1.0));  // the sedan's rear locks once the load has moved forward
  for (int w = 0; w < 4; ++w) EXPECT_NEAR(cs.sample().wheels[w].spin, 0.0, 1e-9) << "wheel " << w;
  ASSERT_TRUE(cs.runUntil(20.0, [&] { return cs.speed() < 0.01; }));
  const double d = stopDistance(v0, muSliding() * p.mass * kG, p.mass);
  // left out: the sedan's rear rolling while the load moves (its brakes hold
  // 900 N m, the patch 1050 at the static load), the last 0.01 m/s: 0.5%
  EXPECT_NEAR((cs.pos() - x0).x(), d, 0.005 * d);
  EXPECT_GT((cs.pos() - x0).x(), 1.1 * v0 * v0 / (2 * muStatic() * kG));  // sliding: longer than at the limit
  EXPECT_NEAR((cs.pos() - x0).y(), 0.0, 0.01);
}

// ABS on: each brake (with rolling resistance) is capped at kAbsShare
// mu_static N r, the patches keep sticking, and the wheels' spin inertia
// decelerates with the car: (m + 4 I / r^2) a = kAbsShare mu_static m g + c v^2.
TEST_P(StickSlipTyreTest, AbsBrakesAtTheStaticFrictionWithoutLocking) {
  const RoadCarParams p = P();
  const double v0 = 100.0 / 3.6;
  CarSim cs = brakingCar(p, carOptions(), v0);
  const Vec3 x0 = cs.pos();
  ASSERT_TRUE(cs.runUntil(1.0));
  for (int w = 0; w < 4; ++w) EXPECT_GT(cs.sample().wheels[w].spin, 1.0) << "wheel " << w << " locked";
  ASSERT_TRUE(cs.runUntil(20.0, [&] { return cs.speed() < 0.01; }));
  const double me = p.mass + 4.0 * p.wheel_inertia / (p.wheel_radius * p.wheel_radius);
  const double d = stopDistance(v0, kAbsShare * muStatic() * p.mass * kG, me);
  // left out: the first 0.3 s while the load moves forward and rings at
  // the ride frequency (the brake limits follow N step by step, the sedan's
  // rear brakes hold less than their patches at first: 900 N m against
  // 1000), and below abs_min_speed (1 m/s) the wheels lock and slide: 2%
  EXPECT_NEAR((cs.pos() - x0).x(), d, 0.02 * d);
  EXPECT_LT((cs.pos() - x0).x(), v0 * v0 / (2 * muSliding() * kG));  // shorter than sliding
  EXPECT_NEAR((cs.pos() - x0).y(), 0.0, 0.01);
}

// A launch on mu 0.3 with constant drive torques T above what the patches
// hold. Traction control off: the driven wheels spin and push at
// mu_sliding N; on: the drive is capped at mu_static N r, the wheels roll.
// Forces: m a = sum F_x - drag, F_x = mu N (spinning), mu N - C_rr N -
// I a / r^2 (driven, rolling), -C_rr N - I a / r^2 (free). Loads: the
// rear gains (h (m a + drag) + sum I omega' + C_rr m g r) / L, the wheels'
// spin-up and rolling resistance being moments on the car too (a spinning
// wheel's I omega' = T - (mu + C_rr) N r is most of it). Solved by fixed point.
TEST_P(StickSlipTyreTest, LaunchOnLowFrictionIsLimitedByTheDrivenAxle) {
  const double mu_ground = 0.3, L = P().wheelbase, h = P().cg_height, m = P().mass, T = 400.0;
  const double r = P().wheel_radius, I = P().wheel_inertia, crr = P().tyre[0].rolling_resistance;
  const bool rear = P().powertrain.drive == Drive::Rear;
  const double share = rear ? P().cg_to_front / L : (L - P().cg_to_front) / L;  // driven axle's static share
  const double sgn = rear ? 1.0 : -1.0;
  for (bool tc : {false, true}) {
    RoadCarParams p = P();
    p.powertrain.present = false;
    p.brakes.traction_control = tc;
    const double mu = tc ? muStatic(mu_ground) : muSliding(mu_ground);
    CarSim cs = makeCar(p, carOptions(2e-3, mu_ground));
    CarControls c;
    for (int w = rear ? 2 : 0; w < (rear ? 4 : 2); ++w) c.wheel_torque[w] = T;  // > mu_static N r ~ 320 N m
    cs.set(c);
    ASSERT_TRUE(cs.runUntil(1.0));
    const double v1 = cs.speed();
    ASSERT_TRUE(cs.runUntil(3.0));
    const double v_mid = 0.5 * (v1 + cs.speed()), drag = dragC() * v_mid * v_mid;
    double ax = 0.0;
    for (int it = 0; it < 100; ++it) {
      double Nd = m * kG * share, spin_moment = 0.0;
      for (int k = 0; k < 2; ++k) {  // the driven load depends on the spin-up, which depends on it
        spin_moment = (tc ? 4.0 : 2.0) * I * ax / r + (tc ? 0.0 : 2.0 * T - (mu + crr) * Nd * r);
        Nd = m * kG * share + sgn * (h * (m * ax + drag) + spin_moment + crr * m * kG * r) / L;
      }
      const double Nf = m * kG - Nd;
      const double Fd = tc ? (mu - crr) * Nd - 2 * I * ax / (r * r) : mu * Nd;
      ax = (Fd - crr * Nf - 2 * I * ax / (r * r) - drag) / m;
    }
    const double a_meas = (cs.speed() - v1) / 2.0;
    // left out: the body's pitch settling after 1 s (the load transfer of a
    // damped rigid body) and the wheels' masses below the centre of mass: 1%
    EXPECT_NEAR(a_meas, ax, 0.01 * ax) << (tc ? "traction control" : "spinning");
    if (!tc) {
      EXPECT_GT(cs.sample().wheels[rear ? 2 : 0].spin * r, 2.0 * cs.speed()) << "the driven wheels spin";
    } else {
      EXPECT_NEAR(cs.sample().wheels[rear ? 2 : 0].spin * r, cs.speed(), 1e-3 * cs.speed()) << "they roll";
    }
  }
}

// Steady cornering on a fixed steer: no slip angles, so the car follows the
// Ackermann geometry's radius (understeer gradient 0) until the patches
// reach their friction; the lateral acceleration it can hold is bounded by
// the friction circles: mu_sliding g <= a_y,max <= mu_static g.
TEST_P(StickSlipTyreTest, CorneringIsNeutralUpToTheFrictionLimit) {
  const RoadCarParams p = P();
  const double L = p.wheelbase, R = 40.0, delta = L / R;
  CarSim cs = makeCar(p, carOptions(), 10.0);
  CarControls c;
  c.steer = delta / p.steering.max_angle;
  double K_meas = 1e9, ay_max = 0.0;
  Vec3 v_prev = cs.vel();
  for (double t = 0.05; t <= 40.0; t += 0.05) {  // a driver ramping the speed at 0.4 m/s^2
    const double v_target = 10.0 + 0.4 * t;
    c.throttle = std::clamp(0.3 + 0.5 * (v_target - cs.speed()), 0.0, 1.0);
    cs.set(c);
    ASSERT_TRUE(cs.runUntil(t));
    const Vec3 v = cs.vel(), a = (v - v_prev) / 0.05, vh = v.normalized();
    v_prev = v;
    ay_max = std::max(ay_max, (a - a.dot(vh) * vh).norm());
    const VehicleSample s = cs.sample();
    const double u = cs.speed(), ay = u * s.yaw_rate;
    if (K_meas > 1e8 && ay > 0.25 * kG) K_meas = (delta - L * s.yaw_rate / u) / ay;
  }
  // the bicycle model with C_f = C_r = infinity: K = 0, against the Magic
  // Formula sedan's 1.6 deg/g. Left out: tan delta against delta and the
  // Ackermann angles' mean (0.05 deg/g), and the speed ramp's drive force
  // and roll rate at the patches: a fifth of the Magic Formula's gradient
  EXPECT_NEAR(K_meas * kG * 180 / kPi, 0.0, 0.3) << "deg/g";
  // at most mu_static m g over all patches (and the loads' roll
  // oscillation as the patches let go, 3%); at least the slide's. The
  // inner and outer tyres of an axle do not share the force in proportion
  // to their loads (docs/vehicles.md), so the outer ones let go first and
  // the car slides a little below mu_sliding g: 5%
  EXPECT_LE(ay_max, 1.03 * muStatic() * kG);
  EXPECT_GE(ay_max, 0.95 * muSliding() * kG);
}

// The ground's friction per place: a locked slide onto an icy patch
// decelerates at the patch's sliding friction, not the scene's.
TEST_P(StickSlipTyreTest, PatchesOfFrictionSetTheSlide) {
  RoadCarParams p = P();
  p.brakes.abs = false;
  FrictionPatch ice;
  ice.x0 = -1e3, ice.x1 = 1e3, ice.y0 = -1e3, ice.y1 = 1e3, ice.mu = 0.1;
  const GroundPtr g = withSurfaceFriction(makePlane(Vec3::UnitZ(), 0.0), {ice});
  const double v0 = 10.0;
  CarSim cs = brakingCar(p, carOptions(2e-3, 1.0), v0, g);
  const Vec3 x0 = cs.pos();
  ASSERT_TRUE(cs.runUntil(60.0, [&] { return cs.speed() < 0.01; }));
  const double d = stopDistance(v0, muSliding(0.1) * p.mass * kG, p.mass);
  EXPECT_NEAR((cs.pos() - x0).x(), d, 0.01 * d);
}

// Over 5 cm bumps at 20 m/s the wheels leave the ground and land, and a
// patch touching with no load (the damper pulling the spring to zero) has
// no friction: the run stays finite and on its bumps, with both
// time-steppers.
TEST_P(StickSlipTyreTest, BumpsAtSpeedStayFinite) {
  for (IntegratorKind k : {IntegratorKind::SemiImplicitEuler, IntegratorKind::VelocityVerlet}) {
    Options o = carOptions(2e-3);
    o.integrator = k;
    CarSim cs = makeCar(P(), o, 20.0, makeSinSinBumps(0.05, 8.0, 14.0));
    CarControls c;
    c.throttle = 0.3;
    cs.set(c);
    ASSERT_TRUE(cs.runUntil(4.0)) << integratorName(k);
    EXPECT_TRUE(cs.sim->state().y.allFinite());
    EXPECT_GT(cs.pos().x(), 60.0);  // kept going at ~20 m/s
  }
}

INSTANTIATE_TEST_SUITE_P(Cars, StickSlipTyreTest, ::testing::Values(Car{"sedan", sedan()}, Car{"hatch", hatch()}),
                         [](const ::testing::TestParamInfo<Car>& i) { return i.param.name; });

std::string buildErrors(const std::string& integrator, const std::string& tyres) {
  try {
    const scenario::Scenario s = scenario::parseScenario(
        R"({"ground": {"type": "plane"}, "contact": {"friction": 1, "friction_model": "regularized"},
            "physics": {"integrator": ")" + integrator + R"("}, "vehicle": {"kind": "road_car", "tyres": )" +
        tyres + "}}");
    scenario::buildScene(s);
  } catch (const scenario::ScenarioError& e) {
    return e.what();
  }
  return "";
}

// The impulses are sized by the step: the ODE integrators are refused with
// the field and the reason; the time-steppers take it.
TEST(StickSlipTyreScenario, OdeIntegratorsAreRefusedAtTheTyreModel) {
  for (const char* i : {"rk4", "implicit_euler", "adaptive"}) {
    const std::string e = buildErrors(i, R"({"model": "stick_slip"})");
    EXPECT_NE(e.find("/vehicle/tyres/model"), std::string::npos) << e;
    EXPECT_NE(e.find(std::string("\"") + i + "\""), std::string::npos) << e;
    EXPECT_NE(e.find("sized by the step"), std::string::npos) << e;
    const std::string rear = buildErrors(i, R"({"front": {}, "rear": {"model": "stick_slip"}})");
    EXPECT_NE(rear.find("/vehicle/tyres/rear/model"), std::string::npos) << rear;
    EXPECT_EQ(buildErrors(i, R"({"model": "magic_formula"})"), "");
  }
  for (const char* i : {"semi_implicit_euler", "velocity_verlet"})
    EXPECT_EQ(buildErrors(i, R"({"model": "stick_slip"})"), "") << i;
}

TEST(StickSlipTyreScenario, UnknownModelsNameTheField) {
  const std::string e = buildErrors("semi_implicit_euler", R"({"model": "brush"})");
  EXPECT_NE(e.find("/vehicle/tyres/model"), std::string::npos) << e;
  EXPECT_NE(e.find("stick_slip"), std::string::npos) << e;  // the choices are listed
  const scenario::Scenario s = scenario::parseScenario(
      std::string(R"({"ground": {"type": "plane"}, "vehicle": {"kind": "road_car", "tyres": {"model": "stick_slip"}}})"));
  EXPECT_FALSE(s.vehicles[0].road.tyre[0].slip_model);
  EXPECT_FALSE(s.vehicles[0].road.tyre[1].slip_model);
}

// configs/sedan_stick_slip.json is the sedan with the stick-slip tyre on
// both axles, and it builds with its semi-implicit Euler.
TEST(StickSlipTyreScenario, ShippedConfigIsTheSedanWithTheCheapTyre) {
  const scenario::Scenario s =
      scenario::loadScenarioFile(std::string(GROUNDSIM_CONFIGS) + "/sedan_stick_slip.json");
  ASSERT_EQ(s.vehicles.size(), 1u);
  EXPECT_FALSE(s.vehicles[0].road.tyre[0].slip_model);
  EXPECT_FALSE(s.vehicles[0].road.tyre[1].slip_model);
  const scenario::Scenario base = scenario::loadScenarioFile(std::string(GROUNDSIM_CONFIGS) + "/sedan.json");
  EXPECT_EQ(s.vehicles[0].road.mass, base.vehicles[0].road.mass);
  EXPECT_EQ(s.vehicles[0].road.tyre[1].sliding_ratio, base.vehicles[0].road.tyre[1].sliding_ratio);
  scenario::Scene scene = scenario::buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  ASSERT_TRUE(scenario::stepScene(scene, sim, 500));  // 2 s of its full-throttle launch
  EXPECT_GT(bodyVel(sim.state().y, sim.model().road_cars[0].body).x(), 5.0);
}

}  // namespace
}  // namespace groundsim::test
