#include "scenario/assets.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

#include <openssl/evp.h>

#include "scenario/object_reader.hpp"
#include "scenario/scenario.hpp"
#include "scenario/scenario_error.hpp"
#include "scenario/terrain_loader.hpp"

namespace groundsim::scenario {

std::string sha256Hex(std::string_view bytes) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), md, &len, EVP_sha256(), nullptr) != 1 || len != 32)
    throw std::runtime_error("SHA-256 failed (OpenSSL)");
  static const char* hex = "0123456789abcdef";
  std::string out(64, '0');
  for (unsigned i = 0; i < 32; ++i) {
    out[2 * i] = hex[md[i] >> 4];
    out[2 * i + 1] = hex[md[i] & 15];
  }
  return out;
}

bool isSha256Hex(std::string_view s) {
  return s.size() == 64 &&
         std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

std::vector<AssetRef> readAssetManifest(const nlohmann::json& doc, IssueList& issues) {
  std::vector<AssetRef> refs;
  if (!doc.is_object() || !doc.contains("assets")) return refs;
  const nlohmann::json& m = doc["assets"];
  if (!m.is_object()) {
    issues.add("/assets", "expected an object (file name -> {\"sha256\", \"size\"}), got " + jsonTypeName(m));
    return refs;
  }
  if (m.size() > kMaxAssets) {
    issues.add("/assets", std::to_string(m.size()) + " files, at most " + std::to_string(kMaxAssets));
    return refs;
  }
  for (const auto& [name, entry] : m.items()) {
    const std::string path = "/assets/" + pointerToken(name);
    if (name.empty() || name.size() > kMaxAssetNameBytes) {
      issues.add(path, "a file name of 1 to " + std::to_string(kMaxAssetNameBytes) + " bytes, got " +
                           std::to_string(name.size()));
      continue;
    }
    if (!entry.is_object()) {
      issues.add(path, "expected an object {\"sha256\", \"size\"}, got " + jsonTypeName(entry));
      continue;
    }
    AssetRef ref;
    ref.name = name;
    bool ok = true;
    for (const auto& [key, v] : entry.items())
      if (key != "sha256" && key != "size") {
        issues.add(path + "/" + pointerToken(key), "unknown key (an asset has \"sha256\" and \"size\")");
        ok = false;
      }
    const auto hash = entry.find("sha256");
    if (hash == entry.end() || !hash->is_string() || !isSha256Hex(hash->get<std::string>())) {
      issues.add(path + "/sha256", hash == entry.end() ? "missing required key (64 lowercase hex digits)"
                                                       : "must be 64 lowercase hex digits (SHA-256)");
      ok = false;
    } else {
      ref.sha256 = hash->get<std::string>();
    }
    const auto size = entry.find("size");
    if (size == entry.end() || !size->is_number_unsigned() ||
        size->get<std::uint64_t>() > kMaxDeclaredAssetBytes) {
      issues.add(path + "/size", size == entry.end() ? "missing required key (bytes, an integer >= 0)"
                                                     : "must be an integer number of bytes in [0, 2^40]");
      ok = false;
    } else {
      ref.size = size->get<std::uint64_t>();
    }
    if (ok) refs.push_back(std::move(ref));
  }
  return refs;
}

std::vector<AssetRef> assetManifest(const nlohmann::json& doc) {
  IssueList issues;
  auto refs = readAssetManifest(doc, issues);
  issues.throwIfAny();
  return refs;
}

std::vector<std::string> namedFiles(const nlohmann::json& doc) {
  const FileAccess collect = FileAccess::collect();
  try {
    // the ground is read before the budget is checked: a scenario the
    // server would refuse still names its files here
    parseScenario(doc, Budget{}, collect);
  } catch (const std::exception&) {
    // problems are the server's to report; the names were collected before
  }
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (const std::string& n : *collect.collected)
    if (seen.insert(n).second) out.push_back(n);
  return out;
}

std::vector<Asset> attachAssets(nlohmann::json& doc, const std::string& base_dir, std::uint64_t max_bytes) {
  std::vector<Asset> assets;
  nlohmann::json manifest = nlohmann::json::object();
  IssueList issues;
  for (const std::string& name : namedFiles(doc)) {
    try {
      const auto path = resolveTerrainPath(FileAccess::local(base_dir), name);
      auto bytes = std::make_shared<const std::string>(readFileBytes(path, max_bytes));
      Asset a{{name, sha256Hex(*bytes), bytes->size()}, bytes};
      manifest[name] = {{"sha256", a.ref.sha256}, {"size", a.ref.size}};
      assets.push_back(std::move(a));
    } catch (const TerrainError& e) {
      issues.add("/assets/" + pointerToken(name), e.what());
    }
  }
  issues.throwIfAny();
  if (doc.is_object()) {
    if (assets.empty()) doc.erase("assets");
    else doc["assets"] = std::move(manifest);
  }
  return assets;
}

}  // namespace groundsim::scenario
