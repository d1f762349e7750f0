#include "bridge/scene_view.hpp"

#include "bridge/race_relay.hpp"

#include "bridge/object_layout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "scenario/bots_override.hpp"

namespace groundsim::web {
namespace {

using nlohmann::json;

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }
json quat(const Quat& q) { return json::array({q.w(), q.x(), q.y(), q.z()}); }

// Radial (body-vertical) stiffness of a wheel's coupling to its carrier:
// sum of k (u . z)^2 over the springs joining them, u the spring's rest
// direction. Springs in series (deformable tyres) are not combined: it is
// the coupling's stiffness, for drawing the deflection N / k.
double radialStiffness(const Model& m, const State& s, int wheel_body, int carrier, const Mat3& Rc) {
  const Vec3 up = Rc.col(2);
  double k = 0.0;
  for (const Spring& sp : m.springs) {
    const Point& a = m.points[sp.a];
    const Point& b = m.points[sp.b];
    const bool joins = (a.body == wheel_body && b.body == carrier) || (a.body == carrier && b.body == wheel_body);
    if (!joins) continue;
    if (sp.isotropic) {
      k += sp.stiffness;
      continue;
    }
    auto world = [&](const Point& p) {
      return Vec3(bodyPos(s.y, p.body) + bodyRot(s.y, p.body).toRotationMatrix() * p.local);
    };
    const Vec3 d = world(b) - world(a);
    if (d.norm() < 1e-12) continue;
    const double c = d.normalized().dot(up);
    k += sp.stiffness * c * c;
  }
  return k;
}

// A road car's wheels are not model wheels: they sit on struts along the
// body's z (physics/road_car/road_car.hpp), at RoadCar::hub at zero travel; the page
// raises each by the suspension travel the car state reports ("strut").
json roadCarLayout(const Model& m, const RoadCar& rc) {
  const RoadCarParams& p = rc.p;
  json jw = json::array();
  for (int i = 0; i < 4; ++i) {
    const Vec3& hub = rc.hub[static_cast<size_t>(i)];
    jw.push_back({{"offset", vec(hub)},
                  {"rotation", quat(Quat::Identity())},
                  {"axis", vec(Vec3::UnitY())},
                  {"radius", p.wheel_radius},
                  {"steerable", i < 2},
                  {"max_steer", i < 2 ? p.steering.max_angle : 0.0},
                  {"pivot", vec(hub)},
                  {"radial_stiffness", 0.0},
                  {"strut", true}});
  }
  // the body box: axle to axle plus overhangs, track wide, from the hubs to
  // roughly a saloon's roof (a drawing, not a collision shape)
  const double front = rc.hub[0].x(), rear = rc.hub[2].x(), half = 0.5 * p.track, zh = rc.hub[0].z();
  const Vec3 lo(rear - 0.8, -half - 0.1, zh + 0.05), hi(front + 0.9, half + 0.1, zh + 1.1);
  const int v = rc.vehicle;
  return {{"name", v < static_cast<int>(m.vehicle_names.size()) ? m.vehicle_names[v] : "vehicle"},
          {"lone_wheel", false},
          {"road_car", true},
          {"mass", p.mass},
          {"wheels", jw},
          {"points", json::array()},
          {"springs", json::array()},
          {"body_min", vec(lo)},
          {"body_max", vec(hi)}};
}

json vehicleLayout(const scenario::Scene& scene, int v) {
  const Model& m = *scene.built.model;
  const State& s = scene.built.initial;
  const int chassis = m.vehicle_body[v];
  const Vec3 xc = bodyPos(s.y, chassis);
  const Mat3 Rc = bodyRot(s.y, chassis).toRotationMatrix();

  std::vector<int> wheels;  // model wheel indices in telemetry order
  if (v < static_cast<int>(scene.cars.size()) && scene.cars[v].vehicle == v)
    for (int w : scene.cars[v].wheels)
      if (w >= 0 && w < static_cast<int>(m.wheels.size()) && m.vehicle_of_wheel[w] == v) wheels.push_back(w);
  if (wheels.empty())
    for (int w = 0; w < static_cast<int>(m.wheels.size()); ++w)
      if (m.vehicle_of_wheel[w] == v) wheels.push_back(w);
  // a lone wheel is its own chassis: nothing to place relative to a body
  const bool lone = wheels.size() == 1 && m.wheels[wheels[0]].body == chassis;

  json jw = json::array();
  std::vector<int> part_of_body(m.bodies.size(), -2);
  part_of_body[chassis] = -1;
  for (int i = 0; i < static_cast<int>(wheels.size()); ++i) {
    const Wheel& w = m.wheels[wheels[i]];
    if (!lone) part_of_body[w.body] = i;
    const Vec3 off = lone ? Vec3::Zero() : Vec3(Rc.transpose() * (bodyPos(s.y, w.body) - xc));
    const Quat rel = lone ? Quat::Identity() : Quat(Rc.transpose() * bodyRot(s.y, w.body).toRotationMatrix());
    Vec3 pivot = off;
    for (int p : m.steered_points)
      if (m.points[p].steer_wheel == wheels[i]) pivot = m.points[p].steer_pivot;
    jw.push_back({{"offset", vec(off)},
                  {"rotation", quat(rel)},
                  {"axis", vec(w.axis)},
                  {"radius", w.radius},
                  {"steerable", w.steerable},
                  {"max_steer", w.max_steer},
                  {"pivot", vec(pivot)},
                  {"radial_stiffness", lone ? 0.0 : radialStiffness(m, s, w.body, w.carrier, Rc)}});
  }

  // points of figure 1: [part, steer wheel or -1, x, y, z] in the part's frame
  std::vector<int> index(m.points.size(), -1);
  json pts = json::array();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int p = 0; p < static_cast<int>(m.points.size()); ++p) {
    const Point& pt = m.points[p];
    int part = -2;
    Vec3 local = pt.local;
    if (pt.body >= 0) {
      part = part_of_body[pt.body];
    } else if (pt.particle >= 0 && pt.wheel >= 0) {
      // deformable tyre: rim particles, placed in their wheel's frame at rest
      auto it = std::find(wheels.begin(), wheels.end(), pt.wheel);
      if (it == wheels.end()) continue;
      part = lone ? -1 : static_cast<int>(it - wheels.begin());
      const int wb = m.wheels[pt.wheel].body;
      const Vec3 xp = Eigen::Map<const Vec3>(s.y.data() + particleOffset(static_cast<int>(m.bodies.size()), pt.particle));
      local = bodyRot(s.y, wb).toRotationMatrix().transpose() * (xp - bodyPos(s.y, wb));
    }
    if (part == -2) continue;
    int steer = -1;
    if (part == -1 && pt.steer_wheel >= 0) {
      auto it = std::find(wheels.begin(), wheels.end(), pt.steer_wheel);
      if (it != wheels.end()) steer = static_cast<int>(it - wheels.begin());
    }
    if (part == -1) lo = lo.cwiseMin(local), hi = hi.cwiseMax(local);
    index[p] = static_cast<int>(pts.size());
    pts.push_back({part, steer, local.x(), local.y(), local.z()});
  }
  json springs = json::array();
  for (const Spring& sp : m.springs)
    if (index[sp.a] >= 0 && index[sp.b] >= 0 && springs.size() < 20000)
      springs.push_back({index[sp.a], index[sp.b]});
  if (!std::isfinite(lo.x())) lo = hi = Vec3::Zero();
  return {{"name", v < static_cast<int>(m.vehicle_names.size()) ? m.vehicle_names[v] : "vehicle"},
          {"lone_wheel", lone},
          {"mass", m.bodies[chassis].mass},
          {"wheels", jw},
          {"points", pts},
          {"springs", springs},
          {"body_min", vec(lo)},
          {"body_max", vec(hi)}};
}

}  // namespace

std::shared_ptr<SceneView> makeSceneView(const std::string& scenario_json, const scenario::FileAccess& files) {
  const scenario::Scenario sc = scenario::parseScenario(scenario_json, scenario::Budget{}, files);
  const scenario::Scene scene = scenario::buildScene(sc);
  auto view = std::make_shared<SceneView>();
  view->scenario_json = scenario_json;
  view->name = sc.name;
  view->ground = scene.built.model->ground;
  const Model& m = *scene.built.model;
  json vehicles = json::array();
  for (int v = 0; v < static_cast<int>(m.vehicle_body.size()); ++v) {
    const auto rc = std::find_if(m.road_cars.begin(), m.road_cars.end(),
                                 [v](const RoadCar& c) { return c.vehicle == v; });
    json l = rc != m.road_cars.end() ? roadCarLayout(m, *rc) : vehicleLayout(scene, v);
    view->wheels.push_back(static_cast<int>(l["wheels"].size()));
    view->road_car.push_back(rc != m.road_cars.end());
    vehicles.push_back(std::move(l));
  }
  // the horizon's levels are centred on the vehicles' start
  Vec3 centre = Vec3::Zero();
  for (int b : m.vehicle_body) centre += bodyPos(scene.built.initial.y, b);
  if (!m.vehicle_body.empty()) centre /= static_cast<double>(m.vehicle_body.size());
  view->layout = {{"name", sc.name}, {"ground", scenario::groundKindName(sc.ground.kind)}, {"vehicles", vehicles},
                  {"objects", objectsLayout(m, scene.built.initial)},
                  {"friction", sc.options.contact.friction},
                  {"horizon", horizonGrids(*view->ground, centre.x(), centre.y(), sc.options.contact.friction)}};
  if (sc.race) {
    view->layout["race"] = raceLayout(*sc.race);
    view->layout["track"] = trackRibbon(*view->ground, *sc.race, sc.options.contact.friction);
  }
  return view;
}

bool surfaceHeight(const Ground& g, double x, double y, double z_start, double* z_out) {
  // Newton on z guarded by bisection once a bracket is known; a bracket is
  // sought by doubling steps when Newton stalls (grad_z near 0)
  double z = z_start, lo = -1e9, hi = 1e9;
  Vec3 grad;
  for (int it = 0; it < 100; ++it) {
    const double H = g.eval(Vec3(x, y, z), &grad);
    if (!std::isfinite(H)) return false;
    if (std::abs(H) < 1e-9) {
      *z_out = z;
      return true;
    }
    if (H > 0) hi = std::min(hi, z); else lo = std::max(lo, z);
    double zn = std::abs(grad.z()) > 1e-9 ? z - H / grad.z() : z - H;
    if (!(zn > lo && zn < hi)) zn = (lo > -1e9 && hi < 1e9) ? 0.5 * (lo + hi) : z - H;
    z = zn;
  }
  const double H = g.eval(Vec3(x, y, z), &grad);
  if (!(std::abs(H) < 1e-6)) return false;
  *z_out = z;
  return true;
}

namespace {

// mu at a surface node, rounded to 0.01; kDefaultMu where the ground has no
// say (no patch, off the map): the scene's contact.friction applies there
constexpr double kDefaultMu = -1.0;
double nodeMu(const Ground& g, double x, double y, double z) {
  const double mu = g.friction(Vec3(x, y, z), kDefaultMu);
  return mu == kDefaultMu || !std::isfinite(mu) ? kDefaultMu : std::round(mu * 100.0) / 100.0;
}

}  // namespace

json horizonGrids(const Ground& g, double cx, double cy, double scene_mu, int n, double step0, int levels) {
  json out = json::array();
  double step = step0;
  for (int l = 0; l < levels; ++l, step *= 4.0) {
    const double x0 = std::round(cx / step) * step - step * (n - 1) / 2.0;
    const double y0 = std::round(cy / step) * step - step * (n - 1) / 2.0;
    json z = json::array(), mu = json::array();
    bool varied = false;
    double prev = 0.0, prev_row = 0.0;
    for (int i = 0; i < n; ++i) {
      prev = prev_row;
      for (int j = 0; j < n; ++j) {
        // the mean of 2 x 2 samples a half step apart: a ground that varies
        // faster than the level's step (the cosine's 6 m waves under 64 m
        // steps) averages out instead of aliasing into random hills
        double sum = 0.0, h = 0.0;
        int got = 0;
        for (double dy : {-0.25, 0.25})
          for (double dx : {-0.25, 0.25})
            if (surfaceHeight(g, x0 + (j + dx) * step, y0 + (i + dy) * step, prev, &h)) sum += h, ++got;
        if (!got) {
          z.push_back(nullptr);
          mu.push_back(scene_mu);
          continue;
        }
        const double zm = sum / got;
        prev = zm;
        if (j == 0) prev_row = zm;
        z.push_back(std::round(zm * 100.0) / 100.0);  // centimetres: drawn at >= 4 m spacing
        const double m = nodeMu(g, x0 + j * step, y0 + i * step, zm);
        varied = varied || m != kDefaultMu;
        mu.push_back(m == kDefaultMu ? scene_mu : m);
      }
    }
    json level = {{"x0", x0}, {"y0", y0}, {"n", n}, {"step", step}, {"z", z}};
    if (varied) level["mu"] = mu;
    out.push_back(std::move(level));
  }
  return out;
}

json groundGrid(const Ground& g, double cx, double cy, int n, double step) {
  const double x0 = std::round(cx / step) * step - step * (n - 1) / 2.0;
  const double y0 = std::round(cy / step) * step - step * (n - 1) / 2.0;
  json z = json::array(), mu = json::array();
  bool varied = false;
  double prev_row = 0.0;
  for (int i = 0; i < n; ++i) {
    double prev = prev_row;
    for (int j = 0; j < n; ++j) {
      double h;
      if (surfaceHeight(g, x0 + j * step, y0 + i * step, prev, &h)) {
        // millimetres are plenty for drawing, and keep the text short
        z.push_back(std::round(h * 1000.0) / 1000.0);
        prev = h;
        if (j == 0) prev_row = h;
        const double m = nodeMu(g, x0 + j * step, y0 + i * step, h);
        varied = varied || m != kDefaultMu;
        mu.push_back(m == kDefaultMu ? json(nullptr) : json(m));
      } else {
        z.push_back(nullptr);
        mu.push_back(nullptr);
      }
    }
  }
  json out = {{"x0", x0}, {"y0", y0}, {"n", n}, {"step", step}, {"z", z}};
  // mu by node only where the ground has friction patches or a map there
  // (null: the scene's contact.friction, layout.friction)
  if (varied) out["mu"] = std::move(mu);
  return out;
}

std::string withBots(const std::string& scenario_json, int bots, double skill) {
  json doc = scenario::parseScenarioDocument(scenario_json);
  scenario::BotsChoice choice;
  choice.count = bots;  // -1: the race's own
  if (skill > 0.0) choice.skill = skill;
  scenario::setBots(doc, choice);
  return doc.dump();
}

std::string withVehicles(const std::string& scenario_json, int count, double margin) {
  json doc = scenario::parseScenarioDocument(scenario_json);
  if (count <= 0) return scenario_json;
  // side by side, their bounding circles `margin` apart (the scenario layer
  // refuses overlapping vehicles)
  // the ground's files are not read (FileAccess::collect): only the car is copied
  const scenario::Scenario sc = scenario::parseScenario(scenario_json, scenario::Budget{}, scenario::FileAccess::collect());
  if (sc.vehicles.empty()) return scenario_json;
  const CarParams& p = sc.vehicles[0].params;
  const double spacing =
      2.0 * std::hypot(p.half_length + p.wheel_radius, p.half_width + p.axle_half_length) + margin;
  json base;
  if (doc.contains("vehicle")) {
    base = doc["vehicle"];
    doc.erase("vehicle");
  } else if (doc.contains("vehicles") && doc["vehicles"].is_array() && !doc["vehicles"].empty()) {
    base = doc["vehicles"][0];
  } else {
    return scenario_json;
  }
  // a race's bots (race.bots) drive cars of their own after the players'
  int bots = 0;
  if (doc.contains("race") && doc["race"].is_object() && doc["race"].contains("bots") &&
      doc["race"]["bots"].is_number_integer())
    bots = std::clamp(doc["race"]["bots"].get<int>(), 0, 64);
  json list = json::array();
  for (int i = 0; i < count + bots; ++i) {
    json v = base;
    const std::string name = v.value("name", std::string("car"));
    v["name"] = i < count ? name + "-" + std::to_string(i + 1) : scenario::botName(i - count);
    json& init = v["initial"];
    if (!init.is_object()) init = json::object();
    json pos = init.contains("position") ? init["position"] : json::array({0, 0, 0});
    if (!pos.is_array() || pos.size() != 3) pos = json::array({0, 0, 0});
    pos[1] = (pos[1].is_number() ? pos[1].get<double>() : 0.0) + spacing * i;
    init["position"] = pos;
    list.push_back(v);
  }
  doc["vehicles"] = list;
  return doc.dump();
}

}  // namespace groundsim::web
