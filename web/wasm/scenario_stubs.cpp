// What the page's build of the scenario layer has instead of the three
// files that need libraries Emscripten has no Debian build of: muParser
// (expression grounds), libpng (heightfields and friction maps from files)
// and OpenSSL (the hashes of assets sent with a create). A scenario that
// names one of those is refused here, and the page draws the server's
// states without prediction for it (web/src/predict.js says so).
#include <algorithm>
#include <cctype>
#include <string>

#include "scenario/assets.hpp"
#include "scenario/expression_ground.hpp"
#include "scenario/terrain_loader.hpp"

namespace groundsim::scenario {

ExpressionError::ExpressionError(int position, const std::string& reason)
    : std::runtime_error(reason), position_(position), reason_(reason) {}

ExpressionGround::ExpressionGround(std::string expression, double gradient_bound)
    : text_(std::move(expression)), gradient_bound_(gradient_bound) {
  throw ExpressionError(-1, "expression grounds are not in the page's predictor (no muParser in WebAssembly)");
}
double ExpressionGround::eval(const Vec3&, Vec3*) const { return 0.0; }
void ExpressionGround::heights(const double*, const double*, const double*, int, int, double*) const {}
double ExpressionGround::value(const Vec3&) const { return 0.0; }
std::string ExpressionGround::describe() const { return text_; }
std::unique_ptr<GroundEvaluator> ExpressionGround::makeEvaluator() const { return nullptr; }
std::optional<std::string> refuteGradientBound(const ExpressionGround&, double) { return std::nullopt; }

GridType gridTypeOf(const std::string& name) {
  const auto dot = name.rfind('.');
  std::string ext = dot == std::string::npos ? "" : name.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return GridType::Png;
  if (ext == ".csv" || ext == ".txt") return GridType::Csv;
  return GridType::Unknown;
}

Grid loadGrid(const FileAccess&, const std::string& name, std::size_t) {
  throw TerrainError(name + ": the page's predictor reads no files (grids inline only)");
}

std::string loadFileBytes(const FileAccess&, const std::string& name, std::size_t) {
  throw TerrainError(name + ": the page's predictor reads no files");
}

// the manifest only lists files the server checks; the page reads none
std::vector<AssetRef> readAssetManifest(const nlohmann::json&, IssueList&) { return {}; }

}  // namespace groundsim::scenario
