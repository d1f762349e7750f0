#include "bridge/object_layout.hpp"

namespace groundsim::web {
namespace {

using nlohmann::json;

const char* shapeName(ShapeKind k) {
  switch (k) {
    case ShapeKind::Box: return "box";
    case ShapeKind::Sphere: return "sphere";
    case ShapeKind::Cylinder: return "cylinder";
    case ShapeKind::Capsule: return "capsule";
    case ShapeKind::Cone: return "cone";
  }
  return "box";
}

json shapeJson(const Shape& sh) {
  json j = {{"shape", shapeName(sh.kind)}};
  switch (sh.kind) {
    case ShapeKind::Box:
      j["size"] = {2.0 * sh.half.x(), 2.0 * sh.half.y(), 2.0 * sh.half.z()};
      j["rounding"] = sh.radius;
      break;
    case ShapeKind::Sphere: j["radius"] = sh.radius; break;
    case ShapeKind::Cylinder:
      j["radius"] = sh.radius;
      j["height"] = 2.0 * sh.half_height;
      break;
    case ShapeKind::Capsule:  // half_height is the straight part's: the scenario's height is end to end
      j["radius"] = sh.radius;
      j["height"] = 2.0 * (sh.half_height + sh.radius);
      break;
    case ShapeKind::Cone:
      j["radius"] = sh.radius;
      j["top_radius"] = sh.top_radius;
      j["height"] = 2.0 * sh.half_height;
      break;
  }
  return j;
}

}  // namespace

json objectsLayout(const Model& m, const State& s) {
  json out = json::array();
  for (const SceneObject& o : m.objects) {
    // static: pos and rot are the world pose; with mass: in the body's frame
    Vec3 p = o.pos;
    Quat q(o.rot);
    double mass = 0.0;
    if (o.body >= 0 && o.body < static_cast<int>(m.bodies.size())) {
      const Quat qb = bodyRot(s.y, o.body);
      p = bodyPos(s.y, o.body) + qb.toRotationMatrix() * o.pos;
      q = qb * q;
      mass = m.bodies[o.body].mass;
    }
    q.normalize();
    json j = shapeJson(o.shape);
    j["name"] = o.name;
    j["static"] = o.body < 0;
    j["mass"] = mass;
    j["p"] = {p.x(), p.y(), p.z()};
    j["q"] = {q.w(), q.x(), q.y(), q.z()};
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace groundsim::web
