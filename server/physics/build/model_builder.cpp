#include "physics/build/model_builder.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "physics/build/collision_build.hpp"

namespace groundsim {

namespace {
[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument(what); }
}  // namespace

ModelBuilder::ModelBuilder(Options opt, GroundPtr ground) {
  if (!ground) bad("ground: missing");
  m_.opt = opt;
  m_.ground = std::move(ground);
}

int ModelBuilder::addBody(const BodySpec& spec, int* first_point) {
  const size_t n = spec.points.size();
  if (n == 0) bad("body '" + spec.name + "': has no points");
  if (spec.masses.size() != n || spec.contact.size() != n ||
      !(spec.simulate.empty() || spec.simulate.size() == n))
    bad("body '" + spec.name + "': one mass and one contact flag per point");
  Body b;
  b.name = spec.name;
  Vec3 com = Vec3::Zero();
  for (size_t k = 0; k < n; ++k) {
    if (!(spec.masses[k] >= 0.0) || !std::isfinite(spec.masses[k]))
      bad("body '" + spec.name + "': point mass must be >= 0 and finite");
    b.mass += spec.masses[k];
    com += spec.masses[k] * spec.points[k];
  }
  if (!(b.mass > 0.0)) bad("body '" + spec.name + "': total mass must be > 0");
  com /= b.mass;
  // eq. (8) with L = I Omega: I = sum m (|r|^2 1 - r r^T) about the COM
  for (size_t k = 0; k < n; ++k) {
    const Vec3 r = spec.points[k] - com;
    b.inertia += spec.masses[k] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  Eigen::SelfAdjointEigenSolver<Mat3> eig(b.inertia);
  const double smallest = eig.eigenvalues().minCoeff();
  if (!(smallest > 1e-12 * std::max(1e-30, eig.eigenvalues().maxCoeff())))
    bad("body '" + spec.name + "': inertia is singular (points collinear?)");
  b.inv_inertia = b.inertia.inverse();

  const int id = static_cast<int>(m_.bodies.size());
  const int first = static_cast<int>(m_.points.size());
  for (size_t k = 0; k < n; ++k) {
    if (!spec.simulate.empty() && !spec.simulate[k]) continue;
    Point p;
    p.body = id;
    p.local = spec.points[k] - com;
    p.contact = spec.contact[k];
    if (p.contact) {
      b.has_contact_points = true;
      b.bound_radius = std::max(b.bound_radius, p.local.norm());
    }
    m_.points.push_back(p);
  }
  m_.bodies.push_back(b);
  com_offsets_.push_back(com);
  if (first_point) *first_point = first;

  const Mat3 R = spec.orientation.normalized().toRotationMatrix();
  const Vec3 x = spec.origin + R * com;
  const Mat3 Iw = R * b.inertia * R.transpose();
  const Vec3 L = Iw * spec.angular_velocity;
  const Quat q = spec.orientation.normalized();
  const double row[13] = {x.x(), x.y(), x.z(), q.x(), q.y(), q.z(), q.w(),
                          spec.velocity.x(), spec.velocity.y(), spec.velocity.z(),
                          L.x(), L.y(), L.z()};
  y_.insert(y_.end(), row, row + 13);
  return id;
}

int ModelBuilder::addParticle(double mass, const Vec3& position, const Vec3& velocity, bool contact) {
  if (!(mass > 0.0) || !std::isfinite(mass)) bad("particle: mass must be > 0 and finite");
  const int id = static_cast<int>(m_.particles.size());
  m_.particles.push_back({mass, contact});
  particle_pos_.push_back(position);
  particle_vel_.push_back(velocity);
  Point p;
  p.particle = id;
  p.contact = contact;
  m_.points.push_back(p);
  return static_cast<int>(m_.points.size()) - 1;
}

int ModelBuilder::addSpring(const Spring& s) {
  const int np = static_cast<int>(m_.points.size());
  if (s.a < 0 || s.a >= np || s.b < 0 || s.b >= np || s.a == s.b) bad("spring: invalid points");
  if (!(s.stiffness >= 0.0) || !(s.damping >= 0.0) || !(s.rest_length >= 0.0))
    bad("spring: stiffness, damping and rest length must be >= 0");
  m_.springs.push_back(s);
  return static_cast<int>(m_.springs.size()) - 1;
}

int ModelBuilder::addWheel(const Wheel& w) {
  const int nb = static_cast<int>(m_.bodies.size());
  if (w.body < 0 || w.body >= nb || w.carrier < -1 || w.carrier >= nb || w.body == w.carrier)
    bad("wheel: invalid body or carrier");
  if (!(w.radius > 0.0)) bad("wheel: radius must be > 0");
  Wheel ww = w;
  ww.axis.normalize();
  const int id = static_cast<int>(m_.wheels.size());
  for (int k = w.first_point; k < w.first_point + w.rim_points; ++k) m_.points[k].wheel = id;
  if (w.contact == WheelContact::Circle)
    m_.bodies[w.body].bound_radius = std::max(m_.bodies[w.body].bound_radius, w.radius);
  m_.bodies[w.body].has_contact_points |= w.contact == WheelContact::Circle;
  m_.wheels.push_back(ww);
  m_.vehicle_of_wheel.push_back(current_vehicle_);
  return id;
}

void ModelBuilder::setSteered(int point, int wheel, const Vec3& pivot) {
  Point& p = m_.points.at(point);
  p.steer_wheel = wheel;
  p.steer_pivot = pivot - com_offsets_.at(p.body);
  // steering keeps the distance to the pivot, so bound the sweep
  Body& b = m_.bodies[p.body];
  if (p.contact)
    b.bound_radius = std::max(b.bound_radius, p.steer_pivot.norm() + (p.local - p.steer_pivot).norm());
}

Vec3 ModelBuilder::pointPosition(int point) const {
  const Point& p = m_.points.at(point);
  if (p.body < 0) return particle_pos_.at(p.particle);
  const double* row = y_.data() + 13 * p.body;
  const Quat q(row[6], row[3], row[4], row[5]);
  return Vec3(row[0], row[1], row[2]) + q.toRotationMatrix() * p.local;
}

int ModelBuilder::beginVehicle(const std::string& name) {
  m_.vehicle_names.push_back(name);
  m_.vehicle_body.push_back(-1);
  current_vehicle_ = static_cast<int>(m_.vehicle_names.size()) - 1;
  return current_vehicle_;
}

void ModelBuilder::setVehicleBody(int body) { m_.vehicle_body.at(current_vehicle_) = body; }

void ModelBuilder::addRoadCar(const RoadCar& car, const std::array<double, kRoadCarStates>& initial) {
  RoadCar rc = car;
  rc.aux = m_.aux_states;
  m_.road_cars.push_back(rc);
  m_.aux_states += kRoadCarStates;
  aux_.insert(aux_.end(), initial.begin(), initial.end());
}

int ModelBuilder::addCollisionGroup(const CollisionGroup& g) {
  m_.groups.push_back(g);
  return static_cast<int>(m_.groups.size()) - 1;
}

void ModelBuilder::addCollider(Collider c) {
  if (c.group < 0 || c.group >= static_cast<int>(m_.groups.size())) bad("collider: invalid group");
  m_.colliders.push_back(c);
}

void ModelBuilder::addProbe(Probe p) {
  if (p.group < 0 || p.group >= static_cast<int>(m_.groups.size())) bad("probe: invalid group");
  m_.probes.push_back(p);
}

void ModelBuilder::addObject(SceneObject o) {
  m_.objects.push_back(std::move(o));
}

BuiltModel ModelBuilder::build() {
  m_.contact_points.clear();
  m_.steered_points.clear();
  m_.body_point_begin.assign(m_.bodies.size(), 0);
  m_.body_point_end.assign(m_.bodies.size(), 0);
  m_.particle_points.assign(m_.particles.size(), -1);
  for (int k = static_cast<int>(m_.points.size()) - 1; k >= 0; --k) {
    const Point& p = m_.points[k];
    if (p.body >= 0) {
      m_.body_point_begin[p.body] = k;
      if (m_.body_point_end[p.body] == 0) m_.body_point_end[p.body] = k + 1;
    } else {
      m_.particle_points[p.particle] = k;
    }
  }
  m_.spring_fans.clear();
  m_.loose_springs.clear();
  m_.spring_k.clear();
  m_.spring_c.clear();
  m_.spring_rest.clear();
  for (int i = 0; i < static_cast<int>(m_.springs.size());) {
    const Spring& s0 = m_.springs[i];
    int n = 1;
    while (!s0.isotropic && i + n < static_cast<int>(m_.springs.size()) &&
           !m_.springs[i + n].isotropic && m_.springs[i + n].b == s0.b &&
           m_.springs[i + n].a == s0.a + n)
      ++n;
    if (n >= 4) {
      m_.spring_fans.push_back({i, n, s0.a, s0.b});
    } else {
      for (int k = 0; k < n; ++k) m_.loose_springs.push_back(i + k);
    }
    i += n;
  }
  for (const Spring& sp : m_.springs) {
    m_.spring_k.push_back(sp.stiffness);
    m_.spring_c.push_back(sp.damping);
    m_.spring_rest.push_back(sp.rest_length);
  }
  for (int k = 0; k < static_cast<int>(m_.points.size()); ++k) {
    if (m_.points[k].contact) m_.contact_points.push_back(k);
    if (m_.points[k].steer_wheel >= 0) m_.steered_points.push_back(k);
  }
  State s;
  s.y.resize(m_.stateSize());
  for (size_t i = 0; i < y_.size(); ++i) s.y[static_cast<Eigen::Index>(i)] = y_[i];
  const int nb = static_cast<int>(m_.bodies.size());
  for (int j = 0; j < static_cast<int>(particle_pos_.size()); ++j) {
    s.y.segment<3>(particleOffset(nb, j)) = particle_pos_[j];
    s.y.segment<3>(particleOffset(nb, j) + 3) = particle_vel_[j];
  }
  for (size_t i = 0; i < aux_.size(); ++i) s.y[m_.auxBase() + static_cast<Eigen::Index>(i)] = aux_[i];
  s.car_controls.assign(m_.road_cars.size(), CarControls{});
  s.cars.assign(m_.road_cars.size(), CarRuntime{});
  s.controls.assign(m_.wheels.size(), WheelControl{});
  s.applied = s.controls;
  s.h_next = m_.opt.dt;
  finishCollisionModel(m_, s.y);
  return {std::make_shared<const Model>(m_), std::move(s)};
}

}  // namespace groundsim
