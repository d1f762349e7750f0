// Builds a road car: its body (the whole car's mass and inertia, carried by
// six mass points on the principal axes), the derived suspension and tyre
// figures, and its initial states (at rest on its springs, design ride height).
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "physics/build/road_car_builder.hpp"
#include "physics/road_car/tyre.hpp"

namespace groundsim {

CarHandle addRoadCar(ModelBuilder& b, const std::string& name, const RoadCarParams& p, const CarPlacement& at) {
  const auto bad = [&](const std::string& why) { throw std::invalid_argument("road car '" + name + "': " + why); };
  if (!(p.cg_to_front > 0.0 && p.cg_to_front < p.wheelbase)) bad("the centre of mass must lie between the axles");
  if (!(p.mass > 4.0 * p.wheel_mass)) bad("mass must exceed the four wheels' mass");
  const double A = 0.5 * (p.inertia.y() + p.inertia.z() - p.inertia.x());
  const double B = 0.5 * (p.inertia.x() + p.inertia.z() - p.inertia.y());
  const double C = 0.5 * (p.inertia.x() + p.inertia.y() - p.inertia.z());
  if (!(A > 0.0 && B > 0.0 && C > 0.0)) bad("inertia must satisfy the triangle inequalities (a rigid body's do)");

  RoadCar rc;
  rc.p = p;
  for (TyreParams& t : rc.p.tyre) {
    t.shape_c = shapeFactor(t.sliding_ratio);
    t.shape_tan = std::tan(std::numbers::pi / (2.0 * t.shape_c));
    t.inv_relaxation = 1.0 / t.relaxation_length;
    t.inv_peak_slip_ratio = 1.0 / t.peak_slip_ratio;
    t.inv_peak_slip_angle = 1.0 / t.peak_slip_angle;
  }
  const double gmag = b.model().opt.gravity.norm();
  const double a = p.cg_to_front, bb = p.wheelbase - a, r = p.wheel_radius;
  for (int w = 0; w < 4; ++w) {
    const int ax = w < 2 ? 0 : 1;
    const TyreParams& tp = p.tyre[ax];
    const SuspensionParams& sp = p.suspension[ax];
    const double corner = 0.5 * p.mass * gmag * (ax == 0 ? bb : a) / p.wheelbase;  // N, static
    const double sprung = corner / gmag - p.wheel_mass;                            // kg
    rc.static_load[w] = corner;
    rc.nominal_load[w] = tp.nominal_load > 0.0 ? tp.nominal_load : corner;
    rc.inv_nominal_load[w] = 1.0 / rc.nominal_load[w];
    const double kt = tp.vertical_stiffness;
    const double wn = 2.0 * std::numbers::pi * sp.ride_frequency;
    const double k_ride = wn * wn * sprung;
    if (!(k_ride < kt)) bad("ride frequency too high for the tyre's vertical stiffness");
    const double k = k_ride * kt / (kt - k_ride);  // wheel rate in series with the tyre gives k_ride
    rc.spring_rate[w] = k;
    // the damper sits across the spring only: seen through the tyre in
    // series its damping is c (k_t / (k + k_t))^2, so scale up to get zeta
    const double s2 = (k + kt) / kt;
    rc.damper_rate[w] = 2.0 * sp.damping_ratio * std::sqrt(k_ride * sprung) * s2 * s2;
    rc.preload[w] = corner - p.wheel_mass * gmag;
    const double x = ax == 0 ? a : -bb, yv = (w % 2 == 0 ? 0.5 : -0.5) * p.track;
    rc.hub[w] = Vec3(x, yv, r - corner / kt - p.cg_height);
  }

  Mat3 R;
  Vec3 com;
  if (at.on_ground) {
    Vec3 surf, n;
    if (!groundPointBelow(*b.model().ground, at.position.x(), at.position.y(), &surf, &n))
      bad("no ground surface below its position");
    Vec3 f(std::cos(at.yaw), std::sin(at.yaw), 0.0);
    f = (f - f.dot(n) * n).normalized();
    R.col(0) = f;
    R.col(1) = n.cross(f);
    R.col(2) = n;
    com = surf + (p.cg_height + at.clearance) * n;
  } else {
    R = (Eigen::AngleAxisd(at.yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(at.pitch, Vec3::UnitY()) *
         Eigen::AngleAxisd(at.roll, Vec3::UnitX())).toRotationMatrix();
    com = at.position;
  }
  BodySpec body;
  body.name = name + "/body";
  const double d[3] = {std::sqrt(3.0 * A / p.mass), std::sqrt(3.0 * B / p.mass), std::sqrt(3.0 * C / p.mass)};
  for (int axis = 0; axis < 3; ++axis)
    for (double sgn : {1.0, -1.0}) {
      Vec3 q = Vec3::Zero();
      q[axis] = sgn * d[axis];
      body.points.push_back(q);
      body.masses.push_back(p.mass / 6.0);
      body.contact.push_back(false);
    }
  body.origin = com;
  body.orientation = Quat(R);
  body.velocity = at.speed * R.col(0);

  CarHandle h;
  h.vehicle = b.beginVehicle(name);
  h.body = b.addBody(body);
  b.setVehicleBody(h.body);
  rc.vehicle = h.vehicle;
  rc.body = h.body;
  const Body& built = b.model().bodies[static_cast<size_t>(h.body)];
  // positive definite (the car outweighs its wheels): its inverse exists
  rc.inv_mass_body = reducedMassBody(rc, built.mass, built.inertia).inverse();
  std::array<double, kRoadCarStates> init{};
  for (int w = 0; w < 4; ++w) init[static_cast<size_t>(roadAux(w, 2))] = at.speed / r + at.wheel_spin;
  b.addRoadCar(rc, init);
  h.wheels = {-1, -1, -1, -1};
  return h;
}

}  // namespace groundsim
