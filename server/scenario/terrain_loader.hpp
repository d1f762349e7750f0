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

// Largest file read for a grid: a 4097 x 4097 16-bit PNG stored without
// compression is 34 MB; a CSV is bounded by its samples (40 bytes each).
inline constexpr std::size_t kMaxGridFileBytes = 64u << 20;

enum class GridType { Png, Csv, Unknown };
// By the name's extension (.png; .csv or .txt).
GridType gridTypeOf(const std::string& name);

// The grid a scenario names `name`, wherever `access` finds it: among the
// assets sent with the scenario, or as a file (resolveTerrainPath).
Grid loadGrid(const FileAccess& access, const std::string& name, std::size_t max_samples = kMaxTerrainSamples);

// The file `name` under the access rules (see file_access.hpp); throws
// TerrainError naming the rule it breaks or that the file does not exist.
std::filesystem::path resolveTerrainPath(const FileAccess& access, const std::string& name);

// By extension: .png -> readPng, .csv / .txt -> readCsv; others refused.
Grid readGridFile(const std::filesystem::path& path, std::size_t max_samples = kMaxTerrainSamples);
Grid readPng(const std::filesystem::path& path, std::size_t max_samples = kMaxTerrainSamples);
Grid readCsv(const std::filesystem::path& path, std::size_t max_samples = kMaxTerrainSamples);
// The same from a file's bytes; `name` (its extension, its file name in
// messages) as the scenario names it. A PNG's size is checked from its
// header, before any pixel is decoded.
Grid readGridBytes(const std::string& name, const std::string& bytes, std::size_t max_samples = kMaxTerrainSamples);
Grid readPngBytes(const std::string& name, const std::string& bytes, std::size_t max_samples = kMaxTerrainSamples);
Grid readCsvBytes(const std::string& name, const std::string& bytes, std::size_t max_samples = kMaxTerrainSamples);
// The bytes of the file a scenario names `name`, wherever `access` finds
// it (as loadGrid), refused when larger than max_bytes.
std::string loadFileBytes(const FileAccess& access, const std::string& name, std::size_t max_bytes);
// A whole file, refused unread when larger than max_bytes.
std::string readFileBytes(const std::filesystem::path& path, std::size_t max_bytes);

}  // namespace groundsim::scenario
