// `objects` (obstacles: walls, kerbs, boxes, cones...) and `collisions`
// (contact between bodies): docs/contact.md.
#include <cmath>
#include <numbers>
#include <set>

#include "scenario/scenario.hpp"
#include "scenario/sections.hpp"

namespace groundsim::scenario {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const std::vector<std::string> kShapes = {"box", "sphere", "cylinder", "capsule", "cone"};

ShapeKind shapeKind(const std::string& s) {
  if (s == "sphere") return ShapeKind::Sphere;
  if (s == "cylinder") return ShapeKind::Cylinder;
  if (s == "capsule") return ShapeKind::Capsule;
  if (s == "cone") return ShapeKind::Cone;
  return ShapeKind::Box;
}

// The dimensions each kind takes (and only those: a box's "radius" is an
// unknown key, not a silently ignored one).
void readShape(ObjectReader& r, Shape& s) {
  const Range size = Range::closed(1e-3, kMaxObjectSize);
  switch (s.kind) {
    case ShapeKind::Box: {
      s.half = 0.5 * r.vec3("size", Vec3(1.0, 1.0, 1.0), size);
      s.radius = r.number("rounding", 0.0, Range::nonNegative(kMaxObjectSize));
      if (s.radius > s.half.minCoeff())
        r.issue("rounding", "must be at most half the smallest size (" + formatNumber(s.half.minCoeff()) +
                                " m), got " + formatNumber(s.radius));
      return;
    }
    case ShapeKind::Sphere: s.radius = r.number("radius", 0.5, size); return;
    case ShapeKind::Cylinder:
      s.radius = r.number("radius", 0.5, size);
      s.half_height = 0.5 * r.number("height", 1.0, size);
      return;
    case ShapeKind::Capsule: {
      s.radius = r.number("radius", 0.25, size);
      const double h = r.number("height", 1.0, size);  // end to end
      if (h < 2.0 * s.radius)
        r.issue("height", "must be at least twice the radius (" + formatNumber(2.0 * s.radius) + " m), got " +
                              formatNumber(h));
      s.half_height = std::max(0.5 * h - s.radius, 0.0);
      return;
    }
    case ShapeKind::Cone:
      s.radius = r.number("radius", 0.15, size);
      s.top_radius = r.number("top_radius", 0.0, Range::nonNegative(kMaxObjectSize));
      s.half_height = 0.5 * r.number("height", 0.5, size);
      return;
  }
}

}  // namespace

void readCollisions(ObjectReader r, CollisionParams& c) {
  const CollisionParams def;
  c.enabled = r.boolean("enabled", def.enabled);
  c.stiffness = r.number("stiffness", def.stiffness, Range::nonNegative());
  c.damping = r.number("damping", def.damping, Range::closed(-1.0, kMaxMagnitude));
  c.frequency = r.number("frequency", def.frequency, Range::positive(1e4));
  c.damping_ratio = r.number("damping_ratio", def.damping_ratio, Range::nonNegative(10.0));
  c.friction = r.number("friction", def.friction, Range::nonNegative(100.0));
  c.slip_velocity = r.number("slip_velocity", def.slip_velocity, Range::positive(1e3));
  c.probe_spacing = r.number("probe_spacing", def.probe_spacing, Range::closed(0.01, 100.0));
  c.hard_impact_dv = r.number("hard_impact_dv", def.hard_impact_dv, Range::positive(1e6));
  c.min_substeps = r.integer("min_substeps", def.min_substeps, 1, kMaxContactSubsteps);
  r.finish();
}

std::vector<ObjectEntry> readObjects(ObjectReader& top, const std::vector<VehicleSpec>& vehicles) {
  std::vector<ObjectEntry> out;
  const nlohmann::json* arr = top.peek("objects");
  if (arr && arr->is_array() && arr->size() > kMaxObjects) {
    top.issue("objects", std::to_string(arr->size()) + " objects, at most " + std::to_string(kMaxObjects));
    top.allow("objects");
    return out;
  }
  std::set<std::string> names;
  for (const VehicleSpec& v : vehicles) names.insert(v.name);
  for (ObjectReader& r : top.objects("objects")) {
    ObjectEntry e;
    e.path = r.path();
    const std::optional<std::string> name = r.requiredString("name");
    if (name) {
      e.spec.name = *name;
      if (name->empty() || name->size() > 256) r.issue("name", "must be 1 to 256 characters");
      else if (!names.insert(*name).second)
        r.issue("name", quote(*name) + " is already the name of a vehicle or another object");
    }
    const std::optional<std::string> shape = r.requiredChoice("shape", kShapes);
    e.spec.shape.kind = shapeKind(shape.value_or("box"));
    readShape(r, e.spec.shape);
    e.spec.position = r.vec3("position", Vec3::Zero());
    const double yaw = r.number("yaw_deg", 0.0, Range::closed(-360.0, 360.0)) * kDeg;
    const double roll = r.number("roll_deg", 0.0, Range::closed(-180.0, 180.0)) * kDeg;
    const double pitch = r.number("pitch_deg", 0.0, Range::closed(-90.0, 90.0)) * kDeg;
    e.spec.orientation = Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch, Vec3::UnitY()) *
                              Eigen::AngleAxisd(roll, Vec3::UnitX()));
    e.on_ground = r.boolean("on_ground", true);
    e.spec.mass = r.number("mass", 0.0, Range::nonNegative(1e7));
    e.spec.friction = r.number("friction", 0.5, Range::nonNegative(100.0));
    e.spec.velocity = r.vec3("velocity", Vec3::Zero(), Range::closed(-1e3, 1e3));
    r.finish();
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace groundsim::scenario
