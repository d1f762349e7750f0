#include "asset_store.hpp"

#include <algorithm>
#include <chrono>

namespace groundsim::session {
namespace {

std::string bytesText(std::uint64_t n) {
  if (n >= (1ull << 20)) return std::to_string(n >> 20) + " MiB (" + std::to_string(n) + " bytes)";
  return std::to_string(n) + " bytes";
}

std::string who(const AssetPart& p) {
  return "asset \"" + p.name + "\" (sha256 " + p.sha256.substr(0, 12) + "...)";
}

}  // namespace

std::string AssetStore::checkPart(const AssetPart& p) const {
  if (!scenario::isSha256Hex(p.sha256)) return "asset \"" + p.name + "\": sha256 must be 64 lowercase hex digits";
  if (p.name.empty() || p.name.size() > scenario::kMaxAssetNameBytes)
    return "asset name: 1 to " + std::to_string(scenario::kMaxAssetNameBytes) + " bytes";
  if (p.size > limits_.max_asset_bytes)
    return who(p) + ": " + bytesText(p.size) + ", more than this server's limit of " +
           bytesText(limits_.max_asset_bytes) + " (groundsim-server --max-asset-bytes)";
  const int n = assetParts(p.size);
  if (p.nparts != n)
    return who(p) + ": nparts " + std::to_string(p.nparts) + ", but " + std::to_string(p.size) + " bytes make " +
           std::to_string(n) + " parts of at most " + std::to_string(kAssetPartBytes);
  if (p.part < 0 || p.part >= n)
    return who(p) + ": part " + std::to_string(p.part) + " is outside [0, " + std::to_string(n - 1) + "]";
  const std::uint64_t begin = static_cast<std::uint64_t>(p.part) * kAssetPartBytes;
  const std::uint64_t expect = std::min(kAssetPartBytes, p.size - std::min(p.size, begin));
  if (p.data.size() != expect)
    return who(p) + ": part " + std::to_string(p.part) + " carries " + std::to_string(p.data.size()) +
           " bytes, expected " + std::to_string(expect) + " (truncated?)";
  return "";
}

bool AssetStore::makeRoom(std::uint64_t bytes) {
  while (done_bytes_ + pending_bytes_ + bytes > limits_.cache_bytes) {
    // the least recently used asset that no session holds
    auto victim = done_.end();
    for (auto it = done_.begin(); it != done_.end(); ++it)
      if (it->second.bytes.use_count() == 1 && (victim == done_.end() || it->second.last_use < victim->second.last_use))
        victim = it;
    if (victim == done_.end()) return false;
    done_bytes_ -= victim->second.bytes->size();
    done_.erase(victim);
  }
  return true;
}

std::string AssetStore::addPart(const AssetPart& p, TimePoint now) {
  if (std::string why = checkPart(p); !why.empty()) return why;
  std::lock_guard<std::mutex> lk(m_);
  if (auto it = done_.find(p.sha256); it != done_.end()) return "";  // already here: a repeat
  auto it = pending_.find(p.sha256);
  if (it == pending_.end()) {
    const auto mine = std::count_if(pending_.begin(), pending_.end(),
                                    [&](const auto& e) { return e.second.client_id == p.client_id; });
    if (mine >= limits_.max_pending_per_client)
      return who(p) + ": this client has " + std::to_string(mine) + " unfinished uploads, at most " +
             std::to_string(limits_.max_pending_per_client);
    if (!makeRoom(p.size))
      return who(p) + ": " + bytesText(p.size) + " do not fit in this server's asset store (" +
             bytesText(limits_.cache_bytes) + ", groundsim-server --asset-cache-bytes; " +
             bytesText(done_bytes_) + " held by running sessions, " + bytesText(pending_bytes_) +
             " in unfinished uploads)";
    Pending q;
    q.name = p.name;
    q.client_id = p.client_id;
    q.size = p.size;
    q.nparts = p.nparts;
    q.bytes.assign(p.size, '\0');
    q.have.assign(p.nparts, false);
    pending_bytes_ += p.size;
    it = pending_.emplace(p.sha256, std::move(q)).first;
  } else if (it->second.size != p.size) {
    return who(p) + ": announced as " + std::to_string(p.size) + " bytes, but an upload of the same hash is " +
           std::to_string(it->second.size) + " bytes";
  }
  Pending& q = it->second;
  q.last = now;
  if (q.have[p.part]) return "";
  std::copy(p.data.begin(), p.data.end(), q.bytes.begin() + static_cast<std::ptrdiff_t>(p.part * kAssetPartBytes));
  q.have[p.part] = true;
  if (++q.received < q.nparts) return "";
  // the last part: the bytes must be what the hash announced
  auto bytes = std::make_shared<const std::string>(std::move(q.bytes));
  pending_bytes_ -= q.size;
  pending_.erase(it);
  const std::string got = scenario::sha256Hex(*bytes);
  if (got != p.sha256)
    return who(p) + ": the " + std::to_string(bytes->size()) + " bytes received hash to sha256 " + got +
           "; discarded";
  done_bytes_ += bytes->size();
  done_[p.sha256] = Entry{std::move(bytes), ++use_clock_};
  return "";
}

std::shared_ptr<const std::string> AssetStore::find(const std::string& sha256) {
  std::lock_guard<std::mutex> lk(m_);
  auto it = done_.find(sha256);
  if (it == done_.end()) return nullptr;
  it->second.last_use = ++use_clock_;
  return it->second.bytes;
}

std::vector<MissingAsset> AssetStore::missing(const std::vector<scenario::AssetRef>& refs, std::string* why) {
  std::vector<MissingAsset> out;
  if (why) why->clear();
  std::uint64_t total = 0;
  for (const auto& r : refs) total += r.size;
  for (const auto& r : refs)
    if (r.size > limits_.max_asset_bytes) {
      if (why)
        *why = "/assets/" + r.name + "/size: " + bytesText(r.size) + ", more than this server's limit of " +
               bytesText(limits_.max_asset_bytes) + " per file (groundsim-server --max-asset-bytes)";
      return out;
    }
  if (total > limits_.max_session_bytes) {
    if (why)
      *why = "/assets: " + bytesText(total) + " in all, more than this server's limit of " +
             bytesText(limits_.max_session_bytes) + " per scenario (groundsim-server --max-session-asset-bytes)";
    return out;
  }
  std::lock_guard<std::mutex> lk(m_);
  for (const auto& r : refs) {
    auto d = done_.find(r.sha256);
    if (d != done_.end()) {
      d->second.last_use = ++use_clock_;
      continue;
    }
    MissingAsset m;
    m.ref = r;
    m.nparts = assetParts(r.size);
    auto p = pending_.find(r.sha256);
    for (int i = 0; i < m.nparts; ++i)
      if (p == pending_.end() || p->second.size != r.size || !p->second.have[i]) m.parts.push_back(i);
    out.push_back(std::move(m));
  }
  return out;
}

void AssetStore::expire(TimePoint now) {
  std::lock_guard<std::mutex> lk(m_);
  const auto idle = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limits_.pending_timeout));
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (now - it->second.last > idle) {
      pending_bytes_ -= it->second.size;
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
}

AssetStore::Stats AssetStore::stats() {
  std::lock_guard<std::mutex> lk(m_);
  return {done_.size(), pending_.size(), done_bytes_, pending_bytes_};
}

}  // namespace groundsim::session
