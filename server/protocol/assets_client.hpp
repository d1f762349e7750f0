// The client's half of sending a scenario with its files (docs/protocol.md,
// Assets), shared by `groundsim create`, the web bridge and RemoteVecEnv:
// the files the scenario names are read as `groundsim run` reads them
// (relative to the scenario file), hashed and listed in its "assets"
// manifest; the create goes out with hashes only; a server that lacks a
// file answers with asset_want_t (the parts it lacks) and refuses the create
// with ERR_MISSING_ASSETS, and the client sends those parts and creates
// again, up to kAssetRounds times.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/asset_want_t.hpp>

#include "scenario/assets.hpp"

namespace groundsim::net {

// Creates refused for missing assets before a client gives up: the first
// asks, the next ones follow parts lost on the way.
inline constexpr int kAssetRounds = 5;
// Largest file a client sends (the server's own limit may be lower; it says so).
inline constexpr std::uint64_t kMaxAssetBytes = 256ull << 20;

struct ScenarioWithAssets {
  std::string json;                     // the text to send: with its "assets" manifest when it names files
  std::vector<scenario::Asset> assets;  // the files, in manifest order
};

// Adds the files `text` names (read relative to base_dir) and their
// manifest. Text that is not a JSON object, or names no file, goes as it is
// (the server reports what is wrong with it). Throws ScenarioError naming
// the key of a file that cannot be read.
ScenarioWithAssets withAssets(const std::string& text, const std::string& base_dir);

// asset_want_t messages addressed to one client, kept by request id until
// taken. Thread-safe: LCM's receive thread adds, the waiting thread takes.
class AssetWants {
 public:
  explicit AssetWants(std::string client_id = "") : client_id_(std::move(client_id)) {}
  void setClientId(std::string client_id) {
    std::lock_guard<std::mutex> lk(m_);
    client_id_ = std::move(client_id);
  }
  void add(const groundsim::asset_want_t& w);
  // Decodes a datagram of GROUNDSIM_ASSET_WANT and adds it when it is ours.
  void addDatagram(const void* data, int size);
  std::vector<groundsim::asset_want_t> take(std::int64_t request_id);

 private:
  std::string client_id_;
  std::mutex m_;
  std::map<std::int64_t, std::vector<groundsim::asset_want_t>> by_request_;
};

// Publishes the parts the wants ask for; an asset the server lacks without
// a want (lost on the way) goes whole. Returns the parts sent; throws
// std::runtime_error when publishing fails. Pauses briefly between bursts
// so that a large file does not overflow the server's socket buffer.
std::size_t sendWantedParts(lcm::LCM& lcm, const std::string& client_id,
                            const std::vector<scenario::Asset>& assets,
                            const std::vector<groundsim::asset_want_t>& wants);

}  // namespace groundsim::net
