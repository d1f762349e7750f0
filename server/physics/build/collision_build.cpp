#include "physics/build/collision_build.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "physics/core/state.hpp"

namespace groundsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Mat3 zTo(const Vec3& axis) { return Quat::FromTwoVectors(Vec3::UnitZ(), axis.normalized()).toRotationMatrix(); }

// Half of a disc's thickness: the report's wheels are hoops with no width,
// so a disc a third of the radius wide stands for the tyre.
double discHalfWidth(double radius) { return radius / 6.0; }

void addWheelDisc(ModelBuilder& b, int group, int body, const Vec3& centre, const Vec3& axis, double radius) {
  Collider c;
  c.group = group;
  c.body = body;
  c.shape.kind = ShapeKind::Cylinder;
  c.shape.radius = radius;
  c.shape.half_height = discHalfWidth(radius);
  c.pos = centre;
  c.rot = zTo(axis);
  b.addCollider(c);
}

void addRoadCarCollision(ModelBuilder& b, int group, const RoadCar& rc, double spacing) {
  const RoadCarParams& p = rc.p;
  const Vec3 size = roadCarBodySize(p);
  // the box spans the axles' midpoint lengthwise and rises from a third of
  // the wheel radius above the ground to the car's height
  const double clearance = std::min(p.wheel_radius / 3.0, 0.5 * size.z());
  const double x_mid = 0.5 * (rc.hub[0].x() + rc.hub[2].x());
  Collider box;
  box.group = group;
  box.body = rc.body;
  box.shape.kind = ShapeKind::Box;
  box.shape.half = Vec3(0.5 * size.x(), 0.5 * size.y(), 0.5 * (size.z() - clearance));
  box.shape.radius = std::min(0.05, 0.25 * box.shape.half.minCoeff());
  box.pos = Vec3(x_mid, 0.0, -p.cg_height + clearance + box.shape.half.z());
  b.addCollider(box);
  for (const Vec3& q : box.shape.probes(spacing)) {
    b.addProbe(Probe{.group = group, .body = rc.body, .local = box.pos + q});
  }
  for (int w = 0; w < 4; ++w) {
    addWheelDisc(b, group, rc.body, rc.hub[w], Vec3::UnitY(), p.wheel_radius);
    for (const Vec3& d : {Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(-1, 0, 0)}) {
      b.addProbe(Probe{.group = group, .body = rc.body, .local = rc.hub[w] + p.wheel_radius * d});
    }
  }
}

}  // namespace

Vec3 roadCarBodySize(const RoadCarParams& p) {
  Vec3 s = p.body_size;
  if (!(s.x() > 0.0)) s.x() = 1.74 * p.wheelbase;
  if (!(s.y() > 0.0)) s.y() = 1.16 * p.track;
  if (!(s.z() > 0.0)) s.z() = 2.64 * p.cg_height;
  return s;
}

void addVehicleCollision(ModelBuilder& b, int vehicle) {
  const Model& m = b.model();
  const CollisionParams& cp = m.opt.collision;
  CollisionGroup g;
  g.name = m.vehicle_names.at(vehicle);
  g.vehicle = vehicle;
  g.friction = cp.friction;
  g.ref_body = m.vehicle_body.at(vehicle);
  const int group = b.addCollisionGroup(g);
  for (const RoadCar& rc : m.road_cars)
    if (rc.vehicle == vehicle) {
      addRoadCarCollision(b, group, rc, cp.probe_spacing);
      return;
    }
  std::set<int> bodies{m.vehicle_body.at(vehicle)}, wheels;
  for (size_t w = 0; w < m.wheels.size(); ++w)
    if (m.vehicle_of_wheel[w] == vehicle) {
      wheels.insert(static_cast<int>(w));
      bodies.insert(m.wheels[w].body);
    }
  const int chassis = m.vehicle_body.at(vehicle);
  const bool lone = wheels.size() == 1 && m.wheels[*wheels.begin()].body == chassis;
  double radius = 0.0;
  for (int w : wheels) radius = std::max(radius, m.wheels[w].radius);
  // chassis: a rounded box around its points (the report's axle points
  // lie in one plane, so the rounding gives it thickness)
  if (!lone) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (const Point& p : m.points)
      if (p.body == chassis) {
        lo = lo.cwiseMin(p.local);
        hi = hi.cwiseMax(p.local);
      }
    if (lo.x() <= hi.x()) {
      const double round = std::max(0.25 * radius, 0.02);
      Collider c;
      c.group = group;
      c.body = chassis;
      c.shape.kind = ShapeKind::Box;
      c.shape.half = 0.5 * (hi - lo) + Vec3::Constant(round);
      c.shape.radius = round;
      c.pos = 0.5 * (hi + lo);
      b.addCollider(c);
    }
  }
  for (int w : wheels) {
    const Wheel& wh = m.wheels[w];
    addWheelDisc(b, group, wh.body, Vec3::Zero(), wh.axis, wh.radius);
    if (wh.contact == WheelContact::Circle) {
      b.addProbe(Probe{.group = group, .body = wh.body, .wheel = w});
    }
  }
  for (int k = 0; k < static_cast<int>(m.points.size()); ++k) {
    const Point& p = m.points[k];
    const bool mine = p.body >= 0 ? bodies.count(p.body) > 0 : (p.wheel >= 0 && wheels.count(p.wheel) > 0);
    if (!mine) continue;
    b.addProbe(Probe{.group = group, .body = p.body, .particle = p.particle, .point = k});
  }
}

int addSceneObject(ModelBuilder& b, const ObjectSpec& o) {
  CollisionGroup g;
  g.name = o.name;
  g.object = static_cast<int>(b.model().objects.size());
  g.friction = o.friction;
  const int group = b.addCollisionGroup(g);
  const double spacing = b.model().opt.collision.probe_spacing;
  const std::vector<Vec3> probes = o.shape.probes(std::min(spacing, 0.5 * o.shape.bound()));
  SceneObject so;
  so.name = o.name;
  so.group = group;
  so.shape = o.shape;
  if (!(o.mass > 0.0)) {
    const Mat3 R = o.orientation.normalized().toRotationMatrix();
    Collider c;
    c.group = group;
    c.shape = o.shape;
    c.pos = o.position;
    c.rot = R;
    b.addCollider(c);
    for (const Vec3& q : probes) {
      b.addProbe(Probe{.group = group, .local = o.position + R * q});
    }
    so.pos = o.position;
    so.rot = R;
    b.addObject(so);
    return -1;
  }
  // a rigid body: six mass points (not simulated) that give the shape's
  // mass, centre of mass and inertia exactly, and the surface probes as its
  // ground contact points
  Vec3 com;
  Mat3 I;
  o.shape.massProperties(o.mass, &com, &I);
  const Vec3 d = I.diagonal();
  const double third = o.mass / 3.0;
  const double dx2 = std::max(0.5 * (d.y() + d.z() - d.x()) / third, 0.0);
  const double dy2 = std::max(0.5 * (d.x() + d.z() - d.y()) / third, 0.0);
  const double dz2 = std::max(0.5 * (d.x() + d.y() - d.z()) / third, 0.0);
  const double dd[3] = {std::sqrt(dx2), std::sqrt(dy2), std::sqrt(dz2)};
  BodySpec body;
  body.name = o.name;
  for (int axis = 0; axis < 3; ++axis)
    for (double sgn : {1.0, -1.0}) {
      Vec3 q = com;
      q[axis] += sgn * dd[axis];
      body.points.push_back(q);
      body.masses.push_back(o.mass / 6.0);
      body.contact.push_back(false);
      body.simulate.push_back(false);
    }
  for (const Vec3& q : probes) {
    body.points.push_back(q);
    body.masses.push_back(0.0);
    body.contact.push_back(true);
    body.simulate.push_back(true);
  }
  const Quat q = o.orientation.normalized();
  body.origin = o.position;
  body.orientation = q;
  body.velocity = o.velocity;
  int first = 0;
  const int id = b.addBody(body, &first);
  const Vec3 off = b.bodyComOffset(id);
  Collider c;
  c.group = group;
  c.body = id;
  c.shape = o.shape;
  c.pos = -off;
  b.addCollider(c);
  for (int k = 0; k < static_cast<int>(probes.size()); ++k) {
    b.addProbe(Probe{.group = group, .body = id, .point = first + k});
  }
  so.body = id;
  so.pos = -off;
  b.addObject(so);
  return id;
}

namespace {

Vec3 probeWorld(const Model& m, const Probe& p, const Eigen::VectorXd& y) {
  const int nb = static_cast<int>(m.bodies.size());
  if (p.point >= 0) {
    const Point& pt = m.points[p.point];
    if (pt.body < 0) return y.segment<3>(particleOffset(nb, pt.particle));
    return Vec3(bodyPos(y, pt.body)) + Quat(bodyRot(y, pt.body)).normalized() * pt.local;
  }
  if (p.body < 0) return p.local;
  return Vec3(bodyPos(y, p.body)) + Quat(bodyRot(y, p.body)).normalized() * p.local;
}

// Probes on the outermost 2% of the group along each of the six directions
// of its reference body (world axes when static); circles count once.
int faceProbes(const Model& m, const CollisionGroup& g, const Eigen::VectorXd& y) {
  if (g.probe_begin == g.probe_end) return 1;
  const Mat3 R = g.ref_body < 0 ? Mat3::Identity() : Quat(bodyRot(y, g.ref_body)).normalized().toRotationMatrix();
  const Vec3 ref = g.ref_body < 0 ? Vec3::Zero() : Vec3(bodyPos(y, g.ref_body));
  std::vector<Vec3> local;
  for (int i = g.probe_begin; i < g.probe_end; ++i) {
    const Probe& p = m.probes[i];
    const Vec3 w = p.wheel >= 0 ? Vec3(bodyPos(y, p.body)) : probeWorld(m, p, y);
    local.push_back(R.transpose() * (w - ref));
  }
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& v : local) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double tol = 0.02 * std::max((hi - lo).maxCoeff(), 1e-9);
  int most = 1;
  for (int a = 0; a < 3; ++a) {
    int nlo = 0, nhi = 0;
    for (const Vec3& v : local) {
      nlo += v[a] <= lo[a] + tol;
      nhi += v[a] >= hi[a] - tol;
    }
    most = std::max({most, nlo, nhi});
  }
  return most;
}

// Colliders and probes sorted by group (stable: each group's in the order
// added), and each group's ranges in them.
void sortByGroup(Model& m) {
  std::stable_sort(m.colliders.begin(), m.colliders.end(),
                   [](const Collider& a, const Collider& b) { return a.group < b.group; });
  std::stable_sort(m.probes.begin(), m.probes.end(), [](const Probe& a, const Probe& b) { return a.group < b.group; });
  for (CollisionGroup& g : m.groups) {
    g.probe_begin = g.probe_end = g.collider_begin = g.collider_end = 0;
    g.mass = 0.0;
  }
  for (int i = static_cast<int>(m.colliders.size()) - 1; i >= 0; --i) {
    CollisionGroup& g = m.groups[m.colliders[i].group];
    g.collider_begin = i;
    if (g.collider_end == 0) g.collider_end = i + 1;
  }
  for (int i = static_cast<int>(m.probes.size()) - 1; i >= 0; --i) {
    CollisionGroup& g = m.groups[m.probes[i].group];
    g.probe_begin = i;
    if (g.probe_end == 0) g.probe_end = i + 1;
  }
}

// The group's mass (its bodies' and particles') and reference body (the
// one it had, if still among its bodies, else the first; -1: none, fixed).
void setMassAndReference(const Model& m, CollisionGroup& g) {
  std::set<int> bodies, particles;
  for (int i = g.collider_begin; i < g.collider_end; ++i)
    if (m.colliders[i].body >= 0) bodies.insert(m.colliders[i].body);
  for (int i = g.probe_begin; i < g.probe_end; ++i) {
    const Probe& p = m.probes[i];
    if (p.body >= 0) bodies.insert(p.body);
    if (p.particle >= 0) particles.insert(p.particle);
  }
  for (int i : bodies) g.mass += m.bodies[i].mass;
  for (int j : particles) g.mass += m.particles[j].mass;
  if (bodies.empty()) g.ref_body = -1;
  else if (g.ref_body < 0 || !bodies.count(g.ref_body)) g.ref_body = *bodies.begin();
}

// A fixed group's world box: its colliders' boxes and its probes.
void boundFixedGroup(const Model& m, CollisionGroup& g) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (int i = g.collider_begin; i < g.collider_end; ++i) {
    const Collider& c = m.colliders[i];
    const Vec3 e = c.rot.cwiseAbs() * c.shape.extents();  // world box of the rotated box
    lo = lo.cwiseMin(c.pos - e);
    hi = hi.cwiseMax(c.pos + e);
  }
  for (int i = g.probe_begin; i < g.probe_end; ++i) {
    lo = lo.cwiseMin(m.probes[i].local);
    hi = hi.cwiseMax(m.probes[i].local);
  }
  g.lo = lo;
  g.hi = hi;
}

// A moving group's bounds as they are gathered: the sphere about the
// reference body (radius r) and the box in its frame. Parts that turn
// relative to the reference body (wheels spin and steer, steered axle
// points, tyre particles) are held as the sphere they sweep about their
// centre of turning, so the box holds them in any pose; parts fixed to it
// as they are.
struct MovingBounds {
  Vec3 ref;  // the reference body's position
  Mat3 Rt;   // world to its frame
  double r = 0.0;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  // whether every part is fixed to the reference body (a road car, an
  // object with mass): then the box is exact in any pose
  bool rigid = true;

  void hold(const Vec3& centre, const Vec3& half) {
    lo = lo.cwiseMin(centre - half);
    hi = hi.cwiseMax(centre + half);
  }
};

void holdColliders(const Model& m, const CollisionGroup& g, const Eigen::VectorXd& y, MovingBounds& k) {
  for (int i = g.collider_begin; i < g.collider_end; ++i) {
    const Collider& c = m.colliders[i];
    k.rigid = k.rigid && c.body == g.ref_body;
    const Mat3 Rb = Quat(bodyRot(y, c.body)).normalized().toRotationMatrix();
    const Vec3 centre = Vec3(bodyPos(y, c.body)) + Rb * c.pos;
    k.r = std::max(k.r, (centre - k.ref).norm() + c.shape.bound());
    if (c.body == g.ref_body) k.hold(k.Rt * (centre - k.ref), (k.Rt * Rb * c.rot).cwiseAbs() * c.shape.extents());
    else k.hold(k.Rt * (centre - k.ref), Vec3::Constant(c.shape.bound()));
  }
}

// Where probe p (at w) turns about relative to the group's reference body:
// itself when it does not.
Vec3 probePivot(const Model& m, const CollisionGroup& g, const Probe& p, const Eigen::VectorXd& y, const Vec3& w) {
  const Point* pt = p.point >= 0 ? &m.points[p.point] : nullptr;
  Vec3 pivot = w;
  if (pt && pt->steer_wheel >= 0 && pt->body >= 0)
    pivot = Vec3(bodyPos(y, pt->body)) + Quat(bodyRot(y, pt->body)).normalized() * pt->steer_pivot;
  else if (pt && pt->body < 0 && pt->wheel >= 0)
    pivot = bodyPos(y, m.wheels[pt->wheel].body);
  else if (pt && pt->body >= 0 && pt->body != g.ref_body)
    pivot = bodyPos(y, pt->body);
  else if (!pt && p.body >= 0 && p.body != g.ref_body)
    pivot = bodyPos(y, p.body);
  return pivot;
}

void holdProbes(const Model& m, const CollisionGroup& g, const Eigen::VectorXd& y, MovingBounds& k) {
  for (int i = g.probe_begin; i < g.probe_end; ++i) {
    const Probe& p = m.probes[i];
    k.rigid = k.rigid && p.wheel < 0 && p.particle < 0 &&
              (p.point >= 0 ? m.points[p.point].body == g.ref_body && m.points[p.point].steer_wheel < 0
                            : p.body == g.ref_body);
    if (p.wheel >= 0) {
      const double rw = m.wheels[p.wheel].radius;
      k.r = std::max(k.r, (Vec3(bodyPos(y, p.body)) - k.ref).norm() + rw);
      k.hold(k.Rt * (Vec3(bodyPos(y, p.body)) - k.ref), Vec3::Constant(rw));
      continue;
    }
    const Vec3 w = probeWorld(m, p, y);
    k.r = std::max(k.r, (w - k.ref).norm());
    const Vec3 pivot = probePivot(m, g, p, y, w);
    k.hold(k.Rt * (pivot - k.ref), Vec3::Constant((w - pivot).norm()));
  }
}

// A moving group's bound sphere about its reference body and box in its
// frame, from the initial state y.
void boundMovingGroup(const Model& m, CollisionGroup& g, const Eigen::VectorXd& y) {
  MovingBounds k;
  k.ref = bodyPos(y, g.ref_body);
  k.Rt = Quat(bodyRot(y, g.ref_body)).normalized().toRotationMatrix().transpose();
  holdColliders(m, g, y, k);
  holdProbes(m, g, y, k);
  // suspension travel, tyre and spring deflection move parts relative
  // to the reference body: a margin keeps them inside the bound, and the
  // box gets the same margin on every side. A rigid group's parts never
  // move against its reference body, so its box holds them as they are
  // (the broad phase still pads it by the step's motion): two sedans
  // 0.4 m apart are no pair (issue 33). Its sphere keeps the margin.
  g.bound = 1.1 * k.r + 0.05;
  g.box_c = 0.5 * (k.lo + k.hi);
  g.box_h = 0.5 * (k.hi - k.lo) + Vec3::Constant(k.rigid ? 0.0 : 0.1 * k.r + 0.05);
  g.rigid = k.rigid;
}

// A light object on many ground contact points rings faster than the step
// resolves (a 0.5 kg cone on 20 points of a 2000 N/m ground: 280 rad/s);
// such scenes take integrator substeps that keep omega h <= 0.5.
void setObjectGroundContact(Model& m) {
  m.object_substeps = 1;
  const CollisionParams& cp = m.opt.collision;
  for (const SceneObject& o : m.objects) {
    if (o.body < 0) continue;
    // the object's points on its ground face ring at half
    // collision.frequency with collision.damping_ratio, whatever its mass
    // (contact.stiffness is sized for the report's 1.4 kg car: a 3 t box
    // would sink 1.2 m; at 15 Hz any object sinks about 1 mm)
    Body& b = m.bodies[o.body];
    const double n = m.groups[o.group].face_probes, w = kPi * cp.frequency;
    b.ground_stiffness = b.mass * w * w / n;
    b.ground_damping = 2.0 * cp.damping_ratio * b.mass * w / n;
    m.object_substeps = std::max({m.object_substeps, substepsFor(w, cp.damping_ratio, m.opt.dt), cp.min_substeps});
  }
  m.object_substeps = std::min(m.object_substeps, kMaxContactSubsteps);
}

// A rigid or static group's probes in runs of kProbeChunk, each with the
// box of its positions (fixed in the reference body's frame, or the world).
void chunkProbes(Model& m, CollisionGroup& g) {
  g.chunk_begin = g.chunk_end = static_cast<int>(m.probe_chunks.size());
  if (!g.rigid && g.ref_body >= 0) return;
  for (int b = g.probe_begin; b < g.probe_end; b += kProbeChunk) {
    ProbeChunk ch;
    ch.begin = b;
    ch.end = std::min(b + kProbeChunk, g.probe_end);
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (int i = ch.begin; i < ch.end; ++i) {
      const Probe& pr = m.probes[i];
      const Vec3& local = pr.point >= 0 ? m.points[pr.point].local : pr.local;
      lo = lo.cwiseMin(local);
      hi = hi.cwiseMax(local);
    }
    ch.c = 0.5 * (lo + hi);
    ch.h = 0.5 * (hi - lo) + Vec3::Constant(1e-9);
    m.probe_chunks.push_back(ch);
  }
  g.chunk_end = static_cast<int>(m.probe_chunks.size());
}

}  // namespace

void finishCollisionModel(Model& m, const Eigen::VectorXd& y) {
  sortByGroup(m);
  int movable = 0, fixed = 0;
  for (CollisionGroup& g : m.groups) {
    setMassAndReference(m, g);
    if (g.collider_begin == g.collider_end && g.probe_begin == g.probe_end) continue;
    if (g.ref_body < 0) {
      ++fixed;
      boundFixedGroup(m, g);
    } else {
      ++movable;
      boundMovingGroup(m, g, y);
    }
  }
  for (CollisionGroup& g : m.groups) g.face_probes = faceProbes(m, g, y);
  m.probe_chunks.clear();
  for (CollisionGroup& g : m.groups) chunkProbes(m, g);
  m.collisions = m.opt.collision.enabled && (movable >= 2 || (movable >= 1 && fixed >= 1));
  setObjectGroundContact(m);
}

}  // namespace groundsim
