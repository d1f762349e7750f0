#include "bridge/race_relay.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "bridge/scene_view.hpp"

namespace groundsim::web {

using json = nlohmann::json;

std::string RaceRelay::type(const std::string& reason) {
  if (reason.rfind("race: {", 0) != 0) return "";
  // events are few (gates, laps): parsing each is cheap
  const nlohmann::json j = nlohmann::json::parse(reason.begin() + 6, reason.end(), nullptr, false);
  if (!j.is_object()) return "";
  auto t = j.find("type");
  return t != j.end() && t->is_string() ? t->get<std::string>() : "";
}

void RaceRelay::note(const std::string& reason, std::shared_ptr<const std::string> message) {
  const std::string t = type(reason);
  if (t == "race") {
    layout_ = std::move(message);
    standings_.reset();  // a new race (or a reset) starts over
  } else if (t == "standings") {
    standings_ = std::move(message);
  }
}

std::vector<std::shared_ptr<const std::string>> RaceRelay::catchUp() const {
  std::vector<std::shared_ptr<const std::string>> out;
  if (layout_) out.push_back(layout_);
  if (standings_) out.push_back(standings_);
  return out;
}

nlohmann::json raceLayout(const scenario::RaceSpec& race) {
  nlohmann::json gates = nlohmann::json::array(), line = nlohmann::json::array();
  for (const auto& g : race.gates) gates.push_back({g.left[0], g.left[1], g.right[0], g.right[1]});
  for (const auto& p : race.centerline) line.push_back({p[0], p[1]});
  return {{"type", "race"}, {"laps", race.laps}, {"circuit", race.circuit}, {"go", race.countdown},
          {"gates", std::move(gates)}, {"centerline", std::move(line)}, {"half_width", race.half_width}};
}

nlohmann::json trackRibbon(const Ground& g, const scenario::RaceSpec& race, double scene_mu) {
  using Pt = std::array<double, 2>;
  std::vector<Pt> line = race.centerline;
  const double hw = race.half_width;
  if (line.size() < 2 || !(hw > 0.0)) return nullptr;
  if (race.circuit) line.push_back(line.front());  // a circuit's line is closed
  // arc length at each point of the polyline
  std::vector<double> at(line.size(), 0.0);
  for (size_t k = 1; k < line.size(); ++k)
    at[k] = at[k - 1] + std::hypot(line[k][0] - line[k - 1][0], line[k][1] - line[k - 1][1]);
  const double length = at.back();
  if (!(length > 0.0)) return nullptr;
  // the point at arc length s (wrapped on a circuit, clamped on a stage)
  auto point = [&](double s) -> Pt {
    if (race.circuit) s = std::fmod(std::fmod(s, length) + length, length);
    s = std::clamp(s, 0.0, length);
    const size_t k = std::min<size_t>(line.size() - 2, std::upper_bound(at.begin(), at.end(), s) - at.begin() - 1);
    const double seg = at[k + 1] - at[k], u = seg > 0.0 ? (s - at[k]) / seg : 0.0;
    return {line[k][0] + u * (line[k + 1][0] - line[k][0]), line[k][1] + u * (line[k + 1][1] - line[k][1])};
  };
  const int n = std::max(1, static_cast<int>(std::ceil(length / std::max(1.0, length / 1500.0))));
  const double step = length / n;
  const int across = std::max(2, static_cast<int>(std::ceil(2.0 * hw / 1.5)));
  json offsets = json::array();
  for (int j = 0; j <= across; ++j) offsets.push_back(-hw + 2.0 * hw * j / across);
  json xy = json::array(), normal = json::array(), z = json::array(), mu = json::array();
  const int stations = race.circuit ? n : n + 1;  // a circuit's last station is its first
  double prev = 0.0;
  for (int k = 0; k < stations; ++k) {
    const double s = k * step;
    const Pt p = point(s), a = point(s - 3.0), b = point(s + 3.0);
    double tx = b[0] - a[0], ty = b[1] - a[1];
    const double tl = std::hypot(tx, ty);
    tx /= tl, ty /= tl;
    const double nx = -ty, ny = tx;  // to the left of the direction of travel
    xy.push_back({std::round(p[0] * 1000.0) / 1000.0, std::round(p[1] * 1000.0) / 1000.0});
    normal.push_back({std::round(nx * 1e5) / 1e5, std::round(ny * 1e5) / 1e5});
    json row = json::array();
    double centre = prev;
    for (int j = 0; j <= across; ++j) {
      const double o = offsets[j].get<double>();
      double h;
      if (!surfaceHeight(g, p[0] + o * nx, p[1] + o * ny, prev, &h)) {
        row.push_back(nullptr);
        continue;
      }
      prev = h;
      if (2 * j == across || (2 * j < across && 2 * (j + 1) > across)) centre = h;
      row.push_back(std::round(h * 1000.0) / 1000.0);  // millimetres
    }
    z.push_back(std::move(row));
    const double m = g.friction(Vec3(p[0], p[1], centre), -1.0);
    mu.push_back(m < 0.0 || !std::isfinite(m) ? scene_mu : std::round(m * 100.0) / 100.0);
  }
  return {{"closed", race.circuit}, {"half_width", hw}, {"step", step}, {"offsets", std::move(offsets)},
          {"xy", std::move(xy)}, {"normal", std::move(normal)}, {"z", std::move(z)}, {"mu", std::move(mu)}};
}

}  // namespace groundsim::web
