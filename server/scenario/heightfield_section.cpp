// `ground.type: "heightfield"`: the samples from a file or inline, their
// placement and scale, then the spline (physics/ground/heightfield.hpp) built once.
#include <cmath>

#include "scenario/terrain_sections.hpp"

namespace groundsim::scenario {

const std::vector<std::string> kHeightfieldKeys = {"file",         "heights",       "cell_size",
                                                   "origin",       "height_scale",  "height_offset"};

std::optional<Grid> readGridSource(ObjectReader& r, const std::string& file_key, const std::string& inline_key,
                                   const FileAccess& files, double bound) {
  const bool has_file = r.has(file_key), has_rows = r.has(inline_key);
  if (has_file && has_rows) {
    r.allow(file_key);
    r.allow(inline_key);
    r.issue(inline_key, "give either \"" + file_key + "\" or \"" + inline_key + "\", not both");
    return std::nullopt;
  }
  if (!has_file && !has_rows) {
    r.allow(inline_key);
    r.issue(file_key, "missing required key (a PNG or CSV file), or give \"" + inline_key + "\" (rows inline)");
    return std::nullopt;
  }
  if (has_file) {
    const auto name = r.requiredString(file_key);
    if (!name) return std::nullopt;
    if (files.mode == FileAccess::Mode::Collect) {
      // a client finding the files to send: nothing is read
      if (files.collected) files.collected->push_back(*name);
      return std::nullopt;
    }
    try {
      return loadGrid(files, *name);
    } catch (const TerrainError& e) {
      r.issue(file_key, e.what());
      return std::nullopt;
    }
  }
  nlohmann::json* rows = r.array(inline_key);
  if (!rows) return std::nullopt;
  const std::string path = r.pathOf(inline_key);
  Grid g;
  g.ny = static_cast<int>(rows->size());
  bool ok = true;
  for (std::size_t j = 0; j < rows->size() && ok; ++j) {
    const nlohmann::json& row = (*rows)[j];
    const std::string rp = path + "/" + std::to_string(j);
    if (!row.is_array()) {
      r.issues().add(rp, "expected an array (a row of numbers), got " + jsonTypeName(row));
      ok = false;
      break;
    }
    if (j == 0) g.nx = static_cast<int>(row.size());
    if (static_cast<int>(row.size()) != g.nx) {
      r.issues().add(rp, "has " + std::to_string(row.size()) + " values, row 0 has " + std::to_string(g.nx) +
                             " (every row needs the same count)");
      ok = false;
      break;
    }
    if (g.values.size() + row.size() > kMaxTerrainSamples) {
      r.issues().add(path, "more than the limit of " + std::to_string(kMaxTerrainSamples) + " samples");
      ok = false;
      break;
    }
    for (std::size_t i = 0; i < row.size(); ++i) {
      const nlohmann::json& v = row[i];
      if (!v.is_number()) {
        r.issues().add(rp + "/" + std::to_string(i), "expected a number, got " + jsonTypeName(v));
        ok = false;
        break;
      }
      const double x = v.get<double>();
      if (!(std::abs(x) <= bound)) {
        r.issues().add(rp + "/" + std::to_string(i), "must be within +-" + formatNumber(bound) + ", got " +
                                                        formatNumber(x));
        ok = false;
        break;
      }
      g.values.push_back(static_cast<float>(x));
    }
  }
  if (!ok) return std::nullopt;
  if (g.nx < 2 || g.ny < 2) {
    r.issue(inline_key, "is " + std::to_string(g.nx) + " x " + std::to_string(g.ny) +
                            " samples; a grid needs at least 2 x 2");
    return std::nullopt;
  }
  return g;
}

bool scaledGrid(ObjectReader& r, const std::optional<Grid>& grid, const std::string& file_key) {
  if (grid) return grid->bit_depth > 0;
  // the file could not be read (its own issue says why): judge by its name,
  // so that a scale given for a PNG is not reported as a second problem
  const nlohmann::json* name = r.peek(file_key);
  return name && name->is_string() && gridTypeOf(name->get<std::string>()) == GridType::Png;
}

void readHeightfield(ObjectReader& r, GroundSpec& g, const FileAccess& files) {
  std::optional<Grid> grid = readGridSource(r, "file", "heights", files, 1e6);
  const auto cell = r.requiredNumber("cell_size", Range::closed(1e-3, 1e4));
  const Eigen::VectorXd origin = r.vector("origin", Eigen::Vector2d(0.0, 0.0), Range::closed(-1e7, 1e7));
  const double offset = r.number("height_offset", 0.0, Range::closed(-1e6, 1e6));
  // PNG values are fractions of full scale: height_scale turns them into
  // metres; CSV and inline heights are metres already
  double scale = 1.0;
  if (scaledGrid(r, grid, "file")) {
    scale = r.number("height_scale", 1.0, Range::positive(1e5));
  } else if (r.has("height_scale")) {
    r.allow("height_scale");
    r.issue("height_scale", "applies to PNG files only (CSV and inline heights are in metres)");
  } else {
    r.allow("height_scale");
  }
  if (!grid || !cell) return;
  HeightSamples s;
  s.nx = grid->nx;
  s.ny = grid->ny;
  s.cell = *cell;
  s.x0 = origin[0];
  s.y0 = origin[1];
  s.heights = std::move(grid->values);
  if (scale != 1.0 || offset != 0.0)
    for (float& h : s.heights) h = static_cast<float>(scale * h + offset);
  try {
    g.heightfield = std::make_shared<const HeightfieldGround>(std::move(s));
  } catch (const std::invalid_argument& e) {
    r.issue(r.has("file") ? "file" : "heights", e.what());
  }
}

}  // namespace groundsim::scenario
