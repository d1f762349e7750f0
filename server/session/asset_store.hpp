// The server's store of the files that clients send with their scenarios
// (docs/protocol.md, Assets): content-addressed by SHA-256, received in
// parts of one datagram each, checked against the announced hash when the
// last part arrives, then shared by every session whose scenario names
// that hash. Bounded: per asset, per client's unfinished uploads, and in
// total; finished assets no session holds are evicted least recently used
// first, unfinished ones after `pending_timeout` without a part. Thread-safe.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "scenario/assets.hpp"
#include "types.hpp"

namespace groundsim::session {

struct AssetLimits {
  std::uint64_t max_asset_bytes = 64ull << 20;     // one file (a 4097 x 4097 16-bit PNG is at most ~34 MB)
  std::uint64_t max_session_bytes = 128ull << 20;  // every file of one scenario
  std::uint64_t cache_bytes = 512ull << 20;        // everything held: finished and unfinished
  double pending_timeout = 30.0;                   // s without a part: an unfinished upload is dropped
  int max_pending_per_client = 16;                 // unfinished uploads of one client
};

// One part as received (asset_part_t).
struct AssetPart {
  std::string client_id;
  std::string name;    // as the client's scenario names the file (for messages)
  std::string sha256;  // of the whole asset
  std::uint64_t size = 0;
  int part = 0, nparts = 0;
  std::string data;
};

// What a create still lacks of one asset.
struct MissingAsset {
  scenario::AssetRef ref;
  int nparts = 0;
  std::vector<int> parts;  // the parts not received, ascending
};

// A create's client is told what to send: one per missing asset.
struct AssetWant {
  std::int64_t request_id = 0;  // of the create (request_t or vec_request_t)
  std::string client_id;
  MissingAsset missing;
};

// Bytes per part: part i holds bytes [i * kAssetPartBytes, ...), so that an
// asset_part_t (with a name of up to 1 KiB) stays one UDP datagram.
inline constexpr std::uint64_t kAssetPartBytes = 56 * 1024;
inline int assetParts(std::uint64_t size) {
  return size == 0 ? 1 : static_cast<int>((size + kAssetPartBytes - 1) / kAssetPartBytes);
}

class AssetStore {
 public:
  explicit AssetStore(AssetLimits limits = {}) : limits_(limits) {}

  // "" when taken (or a repeat of a part already held), else why it was
  // refused or why the finished asset was discarded (the hash does not
  // match), naming the file.
  std::string addPart(const AssetPart& p, TimePoint now);
  // The finished asset with this hash, or nullptr.
  std::shared_ptr<const std::string> find(const std::string& sha256);
  // What is missing of refs (finished ones are left out); "" in *why, or
  // the reason a ref can never be taken (larger than the limits).
  std::vector<MissingAsset> missing(const std::vector<scenario::AssetRef>& refs, std::string* why);
  // Drops unfinished uploads idle for longer than limits.pending_timeout.
  void expire(TimePoint now);

  struct Stats {
    std::size_t assets = 0, pending = 0;
    std::uint64_t bytes = 0, pending_bytes = 0;
  };
  Stats stats();
  const AssetLimits& limits() const { return limits_; }

 private:
  struct Entry {
    std::shared_ptr<const std::string> bytes;
    std::uint64_t last_use = 0;
  };
  struct Pending {
    std::string name, client_id;
    std::uint64_t size = 0;
    int nparts = 0, received = 0;
    std::string bytes;
    std::vector<bool> have;
    TimePoint last{};
  };
  // Frees room for `bytes` more by evicting finished assets no session
  // holds; false when that is not enough. m_ held.
  bool makeRoom(std::uint64_t bytes);
  std::string checkPart(const AssetPart& p) const;

  AssetLimits limits_;
  std::mutex m_;
  std::map<std::string, Entry> done_;       // by sha256
  std::map<std::string, Pending> pending_;  // by sha256
  std::uint64_t done_bytes_ = 0, pending_bytes_ = 0, use_clock_ = 0;
};

}  // namespace groundsim::session
