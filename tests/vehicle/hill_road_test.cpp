// configs/sedan_hills.json: the sedan on the valley-road heightfield
// (configs/terrain/valley_road.png, scripts/make_terrain.py --valley-road)
// completes healthy, follows the road, and climbs with the power the closed
// form asks: on a grade theta the drive power at the wheels is
//   P = v (m g sin(theta) + rho C_d A v^2 / 2 + C_rr m g cos(theta)) + m_eff v a
// with m g v sin(theta) = m g dz/dt and m_eff = m + 4 I / r^2, integrated
// over the +5% section as an energy balance.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "scenario/scenario.hpp"
#include "sedan.hpp"

namespace groundsim::test {
namespace {

TEST(HillRoad, CompletesHealthyAndClimbsWithThePowerTheGradeNeeds) {
  const scenario::Scenario sc = scenario::loadScenarioFile(std::string(GROUNDSIM_CONFIGS) + "/sedan_hills.json");
  const scenario::Scene scene = scenario::buildScene(sc);
  Simulator sim(scene.built.model, scene.built.initial);
  const RoadCarParams& p = sim.model().road_cars.at(0).p;
  const int body = sim.model().road_cars[0].body;
  const double m = p.mass, g = sim.model().opt.gravity.norm();
  const double m_eff = m + 4 * p.wheel_inertia / (p.wheel_radius * p.wheel_radius);
  const double crr = p.tyre[0].rolling_resistance, k_drag = 0.5 * p.aero.air_density * p.aero.drag_area;
  const double grade = 0.05, theta = std::atan(grade);
  const double dt = sim.model().opt.dt;
  const long long per = std::llround(0.02 / dt);

  // the constant +5% section runs from x = 250 m to 700 m (make_terrain.py):
  // measured from 300 m to 650 m, clear of the blends' wheelbase
  const double x_in = 300.0, x_out = 650.0;
  double work = 0, resist = 0, z_in = NAN, z_out = NAN, v_in = NAN, v_out = NAN, x_max = 0, y_max = 0;
  while (sim.state().t < scene.duration - 1e-9) {
    ASSERT_TRUE(scenario::stepScene(scene, sim, per)) << "diverged at t = " << sim.state().t;
    const Vec3 x = bodyPos(sim.state().y, body), vel = bodyVel(sim.state().y, body);
    const double v = vel.norm();
    x_max = std::max(x_max, x.x());
    y_max = std::max(y_max, std::abs(x.y()));
    if (x.x() >= x_in && std::isnan(z_in)) {
      z_in = x.z();
      v_in = v;
      work = -sim.state().drive_work;
    }
    if (!std::isnan(z_in) && std::isnan(z_out)) {
      // the resistances' work over the section (rectangle rule at 20 ms);
      // the drive work is the integrator's own (State::drive_work)
      resist += (k_drag * v * v + crr * m * g * std::cos(theta)) * v * 0.02;
      if (x.x() >= x_out) {
        z_out = x.z();
        v_out = v;
        work += sim.state().drive_work;
      }
    }
  }
  ASSERT_FALSE(std::isnan(z_out)) << "did not reach x = " << x_out << " m (got " << x_max << ")";
  EXPECT_GT(x_max, 1900.0);  // drives the whole road
  EXPECT_LT(y_max, 1.0);     // and stays on it (the valley floor is y = 0)
  // climbs the grade: dz = 5% of the distance along x
  EXPECT_NEAR(z_out - z_in, grade * (x_out - x_in), 0.01 * grade * (x_out - x_in));
  // nearly steady: the speed changes by less than 10% over the section
  EXPECT_NEAR(v_out, v_in, 0.1 * v_in);
  const double climb = m * g * (z_out - z_in), kinetic = 0.5 * m_eff * (v_out * v_out - v_in * v_in);
  const double need = climb + resist + kinetic;
  std::printf("+5%% section: drive work %.4g J, closed form %.4g J (climb %.4g, resistances %.4g, kinetic %.4g); "
              "dz %.3f m over %.0f m\n", work, need, climb, resist, kinetic, z_out - z_in, x_out - x_in);
  // 2%: the driven tyres' longitudinal slip (~0.7% of the tractive power at
  // this load), the rectangle rule for the resistances, and the body's pitch
  // and heave motion
  EXPECT_NEAR(work, need, 0.02 * need) << "climb " << climb << " J, resistances " << resist << " J, kinetic "
                                       << kinetic << " J";
  // the climb is most of it: the grade term dominates, as on any real hill
  EXPECT_GT(climb, 0.5 * need);
}

}  // namespace
}  // namespace groundsim::test
