#include "bridge/shipped_scenarios.hpp"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bridge/object_layout.hpp"
#include "bridge/scene_view.hpp"
#include "scenario/race_spec.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::web {
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxIdLength = 128;
constexpr std::size_t kMaxScenarios = 1000;  // a folder of thousands is not a lobby
constexpr int kMaxDepth = 4;                 // folders below the configs folder

bool idChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' ||
         c == '-';
}

// The first line of a refusal, short enough for a lobby.
std::string firstLine(const std::string& s) {
  std::string line = s.substr(0, s.find('\n'));
  if (line.size() > 200) line = line.substr(0, 197) + "...";
  return line;
}

// Validates `doc` (a scenario's text) with files read from `dir`; "" when it
// passes, else the first problem.
std::string refusal(const std::string& doc, const scenario::Budget& budget, const std::string& dir) {
  try {
    scenario::parseScenario(doc, budget, scenario::FileAccess::local(dir));
    return "";
  } catch (const std::exception& e) {
    return firstLine(e.what());
  }
}

std::string plural(int n) { return std::to_string(n) + (n == 1 ? " car" : " cars"); }

}  // namespace

bool validConfigId(const std::string& id) {
  if (id.empty() || id.size() > kMaxIdLength || id.size() < 6 || id.compare(id.size() - 5, 5, ".json") != 0)
    return false;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = std::min(id.find('/', start), id.size());
    const std::string part = id.substr(start, end - start);
    if (part.empty() || part == "." || part == ".." || !std::all_of(part.begin(), part.end(), idChar)) return false;
    if (end == id.size()) return true;
    start = end + 1;
  }
}

ShippedList listShippedScenarios(const std::string& dir, double margin, int max_cars) {
  ShippedList out;
  std::error_code ec;
  std::vector<std::string> ids;
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    if (it.depth() >= kMaxDepth) it.disable_recursion_pending();
    std::error_code fe;
    if (it->path().extension() != ".json" || !it->is_regular_file(fe)) continue;
    const std::string id = it->path().lexically_relative(dir).generic_string();
    if (!validConfigId(id)) {
      out.skipped.push_back(id + ": its path is not a valid id (at most 128 characters of [A-Za-z0-9._-/])");
      continue;
    }
    ids.push_back(id);
    if (ids.size() >= kMaxScenarios) break;
  }
  // the top level first (the familiar ones), then each folder's
  auto depth = [](const std::string& s) { return std::count(s.begin(), s.end(), '/'); };
  std::sort(ids.begin(), ids.end(),
            [&](const std::string& a, const std::string& b) { return std::pair(depth(a), a) < std::pair(depth(b), b); });

  scenario::Budget budget;
  budget.source = "server";
  budget.max_vehicles = max_cars;
  for (const std::string& id : ids) {
    const fs::path path = fs::path(dir) / id;
    std::ifstream f(path, std::ios::binary);
    std::stringstream text;
    text << f.rdbuf();
    const std::string doc = text.str();
    const std::string folder = path.parent_path().string();
    ShippedScenario s;
    s.id = id;
    try {
      // within the server's vehicle limit: a scenario of more vehicles than
      // it takes is not offered (its create would be refused)
      const scenario::Scenario sc = scenario::parseScenario(doc, budget, scenario::FileAccess::local(folder));
      s.name = sc.name;
      s.description = sc.description;
      s.vehicles = static_cast<int>(sc.vehicles.size());
      s.output_rate = sc.output_rate;
      if (sc.race) {
        s.race = true;
        s.bots = sc.race->bots;
        s.grid = static_cast<int>(sc.race->grid.size());
      }
    } catch (const std::exception& e) {
      out.skipped.push_back(id + ": " + firstLine(e.what()));
      continue;
    }
    // n copies of its car, as a create with "vehicles": n makes them. More
    // copies never validate where fewer did not (they stand side by side,
    // apart: only the budget and the ground's extent grow with n, and a
    // task naming its car fails from n = 1), so the most that validate are
    // found by bisection: two or three parses, not max_cars.
    auto copiesRefused = [&](int n) {
      try {
        return refusal(withVehicles(doc, n, margin), budget, folder);
      } catch (const std::exception& e) {
        return firstLine(e.what());
      }
    };
    int copies = 0;  // the most known to validate
    s.limit = "at most " + plural(max_cars) + " in a browser's session";
    std::string why = copiesRefused(max_cars);
    if (why.empty()) {
      copies = max_cars;
    } else {
      int refused = max_cars;  // the fewest known to be refused, and why
      while (refused - copies > 1) {
        const int n = (copies + refused) / 2;
        std::string w = copiesRefused(n);
        if (w.empty()) {
          copies = n;
        } else {
          refused = n;
          why = std::move(w);
        }
      }
      s.limit = plural(refused) + " refused: " + why;
    }
    s.min_cars = copies >= 1 ? 1 : s.vehicles;
    s.max_cars = std::max(copies, s.vehicles);
    out.scenarios.push_back(std::move(s));
  }
  return out;
}

nlohmann::json scenarioPreview(const std::string& dir, const std::string& id, int n) {
  using nlohmann::json;
  const fs::path path = fs::path(dir) / id;
  std::ifstream f(path, std::ios::binary);
  std::stringstream text;
  text << f.rdbuf();
  const std::string doc = text.str();
  const scenario::FileAccess files = scenario::FileAccess::local(path.parent_path().string());
  const scenario::Scenario sc = scenario::parseScenario(doc, scenario::Budget{}, files);
  const scenario::Scene scene = scenario::buildScene(sc);  // the ground and the objects as placed, no horizon
  const Ground& ground = *scene.built.model->ground;
  const json placed = objectsLayout(*scene.built.model, scene.built.initial);
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  auto grow = [&](double x, double y, double r) {
    x0 = std::min(x0, x - r), y0 = std::min(y0, y - r), x1 = std::max(x1, x + r), y1 = std::max(y1, y + r);
  };
  json track = nullptr, cars = json::array(), objects = json::array();
  if (sc.race && sc.race->centerline.size() >= 2) {
    json line = json::array();
    for (const auto& q : sc.race->centerline) {
      grow(q[0], q[1], sc.race->half_width + 12.0);
      line.push_back({q[0], q[1]});
    }
    track = {{"centerline", std::move(line)}, {"half_width", sc.race->half_width}, {"closed", sc.race->circuit}};
  }
  for (const auto& v : sc.vehicles) {
    const Vec3& q = v.placement.position;
    cars.push_back({q.x(), q.y(), v.placement.yaw});
    if (track.is_null()) grow(q.x(), q.y(), 30.0);
  }
  for (const auto& o : placed) {
    // seen from above: a box as its footprint turned by its yaw, other shapes as a disc (length = width)
    const double x = o["p"][0].get<double>(), y = o["p"][1].get<double>();
    const double w = o["q"][0].get<double>(), qz = o["q"][3].get<double>();
    double sx = 1.0, sy = 1.0;
    if (o.contains("size")) sx = o["size"][0].get<double>(), sy = o["size"][1].get<double>();
    else if (o.contains("radius")) sx = sy = 2.0 * o["radius"].get<double>();
    objects.push_back({x, y, sx, sy, 2.0 * std::atan2(qz, w)});
    if (track.is_null()) grow(x, y, 0.5 * std::max(sx, sy) + 10.0);
  }
  if (!(x1 > x0)) grow(0.0, 0.0, 30.0);
  const double side = std::max(x1 - x0, y1 - y0);
  const double step = side / (n - 1);
  json grid = groundGrid(ground, 0.5 * (x0 + x1), 0.5 * (y0 + y1), n, step);
  return {{"grid", std::move(grid)}, {"track", std::move(track)}, {"cars", std::move(cars)},
          {"objects", std::move(objects)}, {"friction", sc.options.contact.friction}};
}

}  // namespace groundsim::web
