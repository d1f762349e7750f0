// Reading grids of numbers from files for the ground section: grayscale
// PNG (8 or 16 bit, libpng) and CSV (one row per y, one column per x).
// Every failure is a TerrainError whose message the caller files under the
// key that named the file; nothing here knows JSON.
#pragma once

#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenario/file_access.hpp"

namespace groundsim::scenario {

// The most samples one grid may hold: 4097 x 4097 (a 4096-cell square),
// 64 MiB as floats. Checked before the pixels are decoded.
inline constexpr std::size_t kMaxTerrainSamples = 4097u * 4097u;

class TerrainError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A grid read from a file: values[j * nx + i], row j as stored (PNG rows
// from the top, CSV lines from the first).
struct Grid {
  int nx = 0, ny = 0;
  std::vector<float> values;
  // PNG: values are v / full_scale in [0, 1] (full_scale 255 or 65535);
  // CSV: values as written
  int bit_depth = 0;  // 8 or 16 for PNG, 0 for CSV
};

// The file `name` under the access rules (see file_access.hpp); throws
// TerrainError naming the rule it breaks or that the file does not exist.
std::filesystem::path resolveTerrainPath(const FileAccess& access, const std::string& name);

// By extension: .png -> readPng, .csv / .txt -> readCsv; others refused.
Grid readGridFile(const std::filesystem::path& path, std::size_t max_samples = kMaxTerrainSamples);
Grid readPng(const std::filesystem::path& path, std::size_t max_samples = kMaxTerrainSamples);
Grid readCsv(const std::filesystem::path& path, std::size_t max_samples = kMaxTerrainSamples);

}  // namespace groundsim::scenario
