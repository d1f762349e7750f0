// Files that travel with a scenario (docs/protocol.md, Assets). A client
// that sends a scenario over the network finds the files it names
// (namedFiles), reads them as `groundsim run` would (relative to the
// scenario file), and adds the manifest "/assets": for each name as the
// scenario writes it, the SHA-256 and size of its bytes. The server builds
// from bytes it has checked against that hash, never from its own disk.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario/file_access.hpp"

namespace groundsim::scenario {

class IssueList;  // scenario_error.hpp

struct AssetRef {
  std::string name;    // as the scenario names the file, e.g. "../terrain/hills.png"
  std::string sha256;  // 64 lowercase hex digits
  std::uint64_t size = 0;
};

// A scenario names at most this many distinct files.
inline constexpr std::size_t kMaxAssets = 16;
// A name is at most this long (bytes).
inline constexpr std::size_t kMaxAssetNameBytes = 1024;
// Largest size a manifest may declare (1 TiB): a bound on arithmetic only;
// servers set their own, far smaller limits.
inline constexpr std::uint64_t kMaxDeclaredAssetBytes = 1ull << 40;

std::string sha256Hex(std::string_view bytes);
bool isSha256Hex(std::string_view s);

// The manifest "/assets" of a document (empty when absent), each problem
// recorded under its JSON path (e.g. "/assets/hills.png/sha256").
std::vector<AssetRef> readAssetManifest(const nlohmann::json& doc, IssueList& issues);
// The same, throwing ScenarioError when it is malformed.
std::vector<AssetRef> assetManifest(const nlohmann::json& doc);

// The files the document names (heightfields, friction maps), in document
// order without repeats, found by a validation that reads none of them.
std::vector<std::string> namedFiles(const nlohmann::json& doc);

struct Asset {
  AssetRef ref;
  std::shared_ptr<const std::string> bytes;
};

// Reads every file the document names as `groundsim run` does (relative to
// base_dir; FileAccess::Local), hashes it, and writes the manifest into
// doc["assets"] (replacing one already there). Throws ScenarioError naming
// the key that names a missing or unreadable file, or one larger than
// max_bytes.
std::vector<Asset> attachAssets(nlohmann::json& doc, const std::string& base_dir, std::uint64_t max_bytes);

}  // namespace groundsim::scenario
