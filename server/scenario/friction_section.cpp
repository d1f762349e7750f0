// Friction by place on any ground: `friction_patches` (rectangles and
// circles with a mu or a named surface) and `friction_map` (a grid of mu).
#include <cmath>
#include <map>

#include "scenario/terrain_sections.hpp"

namespace groundsim::scenario {
namespace {

// Peak friction of common surfaces for a road tyre (docs/terrain.md).
const std::map<std::string, double> kSurfaces = {
    {"asphalt", 1.0}, {"wet", 0.6}, {"grass", 0.45}, {"snow", 0.25}, {"ice", 0.1}};

// Every patch is tested at every contact: a bound keeps that cheap.
constexpr std::size_t kMaxPatches = 256;
const Range kMu = Range::closed(0.0, 10.0);

std::vector<std::string> surfaceNames() {
  std::vector<std::string> n;
  for (const auto& [k, v] : kSurfaces) n.push_back(k);
  return n;
}

std::optional<FrictionPatch> readPatch(ObjectReader p) {
  FrictionPatch f;
  if (!p.valid()) return std::nullopt;  // reported by the reader
  f.name = p.string("name", "");
  const bool rect = p.has("region"), circle = p.has("circle");
  bool ok = true;
  if (rect == circle) {
    p.allow("region");
    p.allow("circle");
    p.issue(rect ? "circle" : "region",
            rect ? "give either \"region\" or \"circle\", not both"
                 : "missing required key ([x0, y0, x1, y1] m), or give \"circle\" ([x, y, radius] m)");
    ok = false;
  } else if (rect) {
    const Eigen::VectorXd v = p.vector("region", Eigen::Vector4d::Zero(), Range::closed(-1e7, 1e7));
    f.x0 = v[0];
    f.y0 = v[1];
    f.x1 = v[2];
    f.y1 = v[3];
    if (!(f.x0 < f.x1 && f.y0 < f.y1)) {
      p.issue("region", "must be [x0, y0, x1, y1] with x0 < x1 and y0 < y1");
      ok = false;
    }
  } else {
    f.shape = FrictionPatch::Shape::Circle;
    const Eigen::VectorXd v = p.vector("circle", Eigen::Vector3d::Zero(), Range::closed(-1e7, 1e7));
    f.cx = v[0];
    f.cy = v[1];
    f.radius = v[2];
    if (!(f.radius > 0.0)) {
      p.issue("circle", "must be [x, y, radius] with radius > 0");
      ok = false;
    }
  }
  const bool has_mu = p.has("mu"), has_surface = p.has("surface");
  if (has_mu && has_surface) {
    p.allow("mu");
    p.allow("surface");
    p.issue("surface", "give either \"mu\" or \"surface\", not both");
    ok = false;
  } else if (has_mu) {
    f.mu = p.number("mu", 1.0, kMu);
  } else if (has_surface) {
    const std::string s = p.choice("surface", "asphalt", surfaceNames());
    f.mu = kSurfaces.count(s) ? kSurfaces.at(s) : 1.0;
  } else {
    p.allow("surface");
    p.issue("mu", "missing required key (a number), or give \"surface\" (asphalt, wet, grass, snow, ice)");
    ok = false;
  }
  p.finish();
  if (!ok) return std::nullopt;
  return f;
}

void readFrictionMap(ObjectReader m, GroundSpec& g, const FileAccess& files) {
  std::optional<Grid> grid = readGridSource(m, "file", "values", files, 10.0);
  const auto cell = m.requiredNumber("cell_size", Range::closed(1e-3, 1e4));
  const Eigen::VectorXd origin = m.vector("origin", Eigen::Vector2d(0.0, 0.0), Range::closed(-1e7, 1e7));
  double scale = 1.0;  // PNG: mu per full-scale value
  if (scaledGrid(m, grid, "file")) {
    scale = m.number("mu_scale", 1.0, Range::closed(0.0, 10.0));
  } else if (m.has("mu_scale")) {
    m.allow("mu_scale");
    m.issue("mu_scale", "applies to PNG files only (CSV and inline values are mu)");
  } else {
    m.allow("mu_scale");
  }
  m.finish();
  if (!grid || !cell) return;
  auto map = std::make_shared<FrictionGrid>();
  map->nx = grid->nx;
  map->ny = grid->ny;
  map->cell = *cell;
  map->x0 = origin[0];
  map->y0 = origin[1];
  map->mu = std::move(grid->values);
  for (std::size_t k = 0; k < map->mu.size(); ++k) {
    map->mu[k] = static_cast<float>(scale * map->mu[k]);
    if (!(map->mu[k] >= 0.0f)) {  // a CSV may hold negatives
      m.issue(m.has("file") ? "file" : "values",
              "mu must be >= 0, got " + formatNumber(map->mu[k]) + " at row " + std::to_string(k / map->nx) +
                  ", column " + std::to_string(k % map->nx));
      return;
    }
  }
  g.friction_map = std::move(map);
}

}  // namespace

const std::vector<std::string> kFrictionKeys = {"friction_patches", "friction_map"};

void readSurfaceFriction(ObjectReader& r, GroundSpec& g, const FileAccess& files) {
  if (nlohmann::json* list = r.array("friction_patches")) {
    if (list->size() > kMaxPatches) {
      r.issue("friction_patches", "holds " + std::to_string(list->size()) + " patches, more than the limit of " +
                                      std::to_string(kMaxPatches) + " (use a friction_map)");
    } else {
      for (std::size_t i = 0; i < list->size(); ++i)
        if (auto p = readPatch(ObjectReader((*list)[i], r.pathOf("friction_patches") + "/" + std::to_string(i),
                                            r.issues())))
          g.friction_patches.push_back(std::move(*p));
    }
  }
  if (r.has("friction_map")) readFrictionMap(r.object("friction_map"), g, files);
  else r.allow("friction_map");
}

}  // namespace groundsim::scenario
