#include "physics/build/vehicle.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace groundsim {

namespace {

// Smallest signed distance of a wheel circle above the ground (sampled).
double circleClearance(GroundProbe& g, const Vec3& c, const Vec3& axis, double r) {
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  double best = std::numeric_limits<double>::infinity();
  Vec3 grad;
  for (int k = 0; k < 720; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / 720.0;
    const Vec3 p = c + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
    const double H = g.eval(p, &grad);
    best = std::min(best, H / std::max(grad.norm(), 1e-12));
  }
  return best;
}

// Orientation (x forward, y left, z up) and position of a vehicle's frame:
// with on_ground, aligned with the ground normal below at.position and
// lowered until the lowest of its wheels (centres in the frame, radius r)
// has the requested clearance.
std::pair<Mat3, Vec3> place(const ModelBuilder& b, const std::string& who, const CarPlacement& at, double r,
                            const std::vector<Vec3>& centres) {
  Mat3 R;
  Vec3 origin = at.position;
  if (!at.on_ground) {
    R = (Eigen::AngleAxisd(at.yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(at.pitch, Vec3::UnitY()) *
         Eigen::AngleAxisd(at.roll, Vec3::UnitX())).toRotationMatrix();
    return {R, origin};
  }
  GroundProbe ground(*b.model().ground);
  Vec3 surf, n;
  if (!groundPointBelow(ground, at.position.x(), at.position.y(), &surf, &n))
    throw std::invalid_argument(who + ": no ground surface below its position");
  Vec3 f = Vec3(std::cos(at.yaw), std::sin(at.yaw), 0.0);
  f = (f - f.dot(n) * n).normalized();
  R.col(0) = f;
  R.col(1) = n.cross(f);
  R.col(2) = n;
  origin = surf + R.col(2) * r;
  // settle: move along the vertical until the lowest wheel has the clearance
  for (int it = 0; it < 8; ++it) {
    double low = std::numeric_limits<double>::infinity();
    for (const Vec3& c : centres)
      low = std::min(low, circleClearance(ground, origin + R * c, R.col(1), r));
    if (std::abs(low - at.clearance) < 1e-10) break;
    origin.z() += (at.clearance - low) / std::max(R(2, 2), 0.1);
  }
  return {R, origin};
}

// The bearing: zero-length springs from the wheel's two axle points
// (wheel_axle0, +1) to the carrier's (axle0, +1), a hinge by penalty.
void addBearing(ModelBuilder& b, const CarParams& p, int wheel_axle0, int axle0) {
  for (int side = 0; side < 2; ++side) {
    Spring sp;
    sp.a = wheel_axle0 + side;
    sp.b = axle0 + side;
    sp.stiffness = p.bearing_stiffness;
    sp.damping = p.bearing_damping;
    sp.isotropic = true;
    b.addSpring(sp);
  }
}

Spring spring(const ModelBuilder& b, int a, int c, double k, double d) {
  Spring s;
  s.a = a;
  s.b = c;
  s.stiffness = k;
  s.damping = d;
  s.rest_length = (b.pointPosition(a) - b.pointPosition(c)).norm();  // no prestress
  return s;
}

// A deformable tyre: see CarParams::deformable. Returns the wheel index.
int addDeformableWheel(ModelBuilder& b, const std::string& name, const CarParams& p, const Vec3& centre,
                       const Quat& q, const Vec3& vel, const Vec3& spin, int carrier, int axle0,
                       bool steerable) {
  const int n = p.rim_points;
  const double r = p.wheel_radius, rh = 0.25 * r, a = p.axle_half_length;
  const Mat3 R = q.toRotationMatrix();
  // hub: two rings of n points either side of the wheel plane, plus the
  // two massless bearing points on the axle
  BodySpec hub;
  hub.name = name + "/hub";
  for (double side : {+0.5, -0.5})
    for (int k = 0; k < n; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / n;
      hub.points.push_back(Vec3(rh * std::cos(phi), side * a, rh * std::sin(phi)));
      hub.masses.push_back(p.hub_mass_fraction * p.wheel_mass / (2 * n));
      hub.contact.push_back(false);
    }
  for (double side : {+1.0, -1.0}) {
    hub.points.push_back(Vec3(0, side * a, 0));
    hub.masses.push_back(0.0);
    hub.contact.push_back(false);
  }
  hub.origin = centre;
  hub.orientation = q;
  hub.velocity = vel;
  hub.angular_velocity = spin;
  int first_hub = 0;
  const int hub_body = b.addBody(hub, &first_hub);
  // rim: free point masses moving with the spinning wheel
  const double m_rim = (1.0 - p.hub_mass_fraction) * p.wheel_mass / n;
  int first_rim = -1;
  for (int k = 0; k < n; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / n;
    const Vec3 x = centre + R * Vec3(r * std::cos(phi), 0, r * std::sin(phi));
    const int pt = b.addParticle(m_rim, x, vel + spin.cross(x - centre), true);
    if (k == 0) first_rim = pt;
  }
  // crossed spokes a quarter turn either way to both hub rings, then tread
  const int s = std::max(1, n / 4);
  for (int k = 0; k < n; ++k) {
    for (int ring = 0; ring < 2; ++ring)
      for (int off : {s, -s})
        b.addSpring(spring(b, first_rim + k, first_hub + ring * n + ((k + off) % n + n) % n, p.tyre_stiffness,
                           p.tyre_damping));
    for (int step : {1, 2})
      b.addSpring(spring(b, first_rim + k, first_rim + (k + step) % n, p.tread_stiffness, p.tyre_damping));
  }
  addBearing(b, p, first_hub + 2 * n, axle0);
  Wheel wh;
  wh.body = hub_body;
  wh.carrier = carrier;
  wh.radius = r;
  wh.contact = WheelContact::RimPoints;
  wh.steerable = steerable;
  wh.max_steer = p.max_steer;
  wh.steer_rate = p.steer_rate;
  wh.first_point = first_rim;
  wh.rim_points = n;
  return b.addWheel(wh);
}

}  // namespace

CarHandle addCar(ModelBuilder& b, const std::string& name, const CarParams& p, const CarPlacement& at) {
  if (p.rim_points < 3) throw std::invalid_argument("car: rim_points must be >= 3");
  const double r = p.wheel_radius, a = p.axle_half_length;
  const std::array<Vec3, 4> centres = {Vec3(p.half_length, p.half_width, 0), Vec3(p.half_length, -p.half_width, 0),
                                       Vec3(-p.half_length, p.half_width, 0), Vec3(-p.half_length, -p.half_width, 0)};
  const auto [R, origin] = place(b, "car '" + name + "'", at, r, {centres.begin(), centres.end()});
  const Quat q(R);
  const Vec3 vel = at.speed * R.col(0);

  CarHandle h;
  h.vehicle = b.beginVehicle(name);
  BodySpec body;
  body.name = name + "/body";
  for (const Vec3& c : centres)
    for (double side : {+1.0, -1.0}) {
      body.points.push_back(c + Vec3(0, side * a, 0));
      body.masses.push_back(p.body_mass / 8.0);
      body.contact.push_back(p.body_contact);
    }
  body.origin = origin;
  body.orientation = q;
  body.velocity = vel;
  int first_axle = 0;
  h.body = b.addBody(body, &first_axle);
  b.setVehicleBody(h.body);

  static const char* kWheelNames[4] = {"front_left", "front_right", "rear_left", "rear_right"};
  for (int w = 0; w < 4; ++w) {
    if (p.deformable) {
      h.wheels[w] = addDeformableWheel(b, name + "/" + kWheelNames[w], p, origin + R * centres[w], q, vel,
                                       at.wheel_spin * R.col(1), h.body, first_axle + 2 * w,
                                       w < 2 && p.max_steer > 0.0);
      if (w < 2 && p.max_steer > 0.0)
        for (int s = 0; s < 2; ++s) b.setSteered(first_axle + 2 * w + s, h.wheels[w], centres[w]);
      continue;
    }
    BodySpec ws;
    ws.name = name + "/" + kWheelNames[w];
    const bool rim_contact = p.wheel_contact == WheelContact::RimPoints;
    for (int k = 0; k < p.rim_points; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / p.rim_points;
      ws.points.push_back(Vec3(r * std::cos(phi), 0.0, r * std::sin(phi)));
      ws.masses.push_back(p.wheel_mass / p.rim_points);
      ws.contact.push_back(rim_contact);
      // a continuous wheel needs its rim for inertia only, unless the rim
      // springs hang on it
      ws.simulate.push_back(rim_contact || p.coupling == WheelCoupling::RimSprings);
    }
    if (p.coupling == WheelCoupling::Bearing) {  // massless attachment points on the axle
      for (double side : {+1.0, -1.0}) {
        ws.points.push_back(Vec3(0, side * a, 0));
        ws.masses.push_back(0.0);
        ws.contact.push_back(false);
        ws.simulate.push_back(true);
      }
    }
    ws.origin = origin + R * centres[w];
    ws.orientation = q;
    ws.velocity = vel;
    ws.angular_velocity = at.wheel_spin * R.col(1);
    int first_rim = 0;
    const int wb = b.addBody(ws, &first_rim);
    const bool rim_kept = ws.simulate.front();

    const int axle0 = first_axle + 2 * w;  // +a side, then -a side
    if (p.coupling == WheelCoupling::RimSprings) {
      // axle point outer, rim point inner: each axle's springs form a fan
      // the force loop runs over contiguously
      for (int s = 0; s < 2; ++s)
        for (int k = 0; k < p.rim_points; ++k) {
          Spring sp;
          sp.a = first_rim + k;
          sp.b = axle0 + s;
          sp.stiffness = p.rim_stiffness;
          sp.damping = p.rim_damping;
          sp.rest_length = (b.pointPosition(sp.a) - b.pointPosition(sp.b)).norm();
          b.addSpring(sp);
        }
    } else {
      addBearing(b, p, first_rim + (rim_kept ? p.rim_points : 0), axle0);
    }
    Wheel wh;
    wh.body = wb;
    wh.carrier = h.body;
    wh.axis = Vec3::UnitY();
    wh.radius = r;
    wh.contact = p.wheel_contact;
    wh.steerable = w < 2 && p.max_steer > 0.0;
    wh.max_steer = p.max_steer;
    wh.steer_rate = p.steer_rate;
    wh.first_point = first_rim;
    wh.rim_points = rim_kept ? p.rim_points : 0;
    h.wheels[w] = b.addWheel(wh);
    if (wh.steerable)
      for (int s = 0; s < 2; ++s) b.setSteered(axle0 + s, h.wheels[w], centres[w]);
  }
  return h;
}

}  // namespace groundsim

namespace groundsim {

CarHandle addLoneWheel(ModelBuilder& b, const std::string& name, const CarParams& p, const CarPlacement& at) {
  if (p.rim_points < 3) throw std::invalid_argument("wheel: rim_points must be >= 3");
  const auto [R, origin] = place(b, "wheel '" + name + "'", at, p.wheel_radius, {Vec3::Zero()});
  CarHandle h;
  h.vehicle = b.beginVehicle(name);
  BodySpec ws;
  ws.name = name;
  const bool rim_contact = p.wheel_contact == WheelContact::RimPoints;
  for (int k = 0; k < p.rim_points; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / p.rim_points;
    ws.points.push_back(Vec3(p.wheel_radius * std::cos(phi), 0.0, p.wheel_radius * std::sin(phi)));
    ws.masses.push_back(p.wheel_mass / p.rim_points);
    ws.contact.push_back(rim_contact);
    ws.simulate.push_back(rim_contact);
  }
  ws.origin = origin;
  ws.orientation = Quat(R);
  ws.velocity = at.speed * R.col(0);
  ws.angular_velocity = at.wheel_spin * R.col(1);
  int first = 0;
  h.body = b.addBody(ws, &first);
  b.setVehicleBody(h.body);
  Wheel wh;
  wh.body = h.body;
  wh.carrier = -1;
  wh.radius = p.wheel_radius;
  wh.contact = p.wheel_contact;
  wh.first_point = first;
  wh.rim_points = rim_contact ? p.rim_points : 0;
  h.wheels = {b.addWheel(wh), -1, -1, -1};
  return h;
}

}  // namespace groundsim
