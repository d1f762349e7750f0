#include "protocol/assets_client.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include <groundsim/asset_part_t.hpp>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "scenario/json_limits.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::net {
namespace {

// Bytes per part: as the server's (session/asset_store.hpp, kAssetPartBytes)
// and asset_part_t's comment; a part is one datagram.
constexpr std::uint64_t kPartBytes = 56 * 1024;
// A pause after every this many bytes: 2 MiB at a time stays far inside
// the server's 8 MiB receive buffer while it copies the parts out.
constexpr std::uint64_t kBurstBytes = 2u << 20;

int partsOf(std::uint64_t size) { return size == 0 ? 1 : static_cast<int>((size + kPartBytes - 1) / kPartBytes); }

std::int64_t nowMicros() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

}  // namespace

ScenarioWithAssets withAssets(const std::string& text, const std::string& base_dir) {
  ScenarioWithAssets out{text, {}};
  // nlohmann's parser recurses once per level: a document past the default
  // limits (depth, size) goes as it is, for the server to refuse
  scenario::IssueList limits;
  scenario::scanText(text, scenario::Budget{}, limits);
  if (!limits.empty()) return out;
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded() || !doc.is_object()) return out;
  if (scenario::namedFiles(doc).empty()) return out;
  out.assets = scenario::attachAssets(doc, base_dir, kMaxAssetBytes);
  out.json = doc.dump();
  return out;
}

void AssetWants::add(const groundsim::asset_want_t& w) {
  std::lock_guard<std::mutex> lk(m_);
  if (w.client_id != client_id_) return;
  // a client asks again only for its latest creates: keep a few
  if (by_request_.size() > 64) by_request_.erase(by_request_.begin());
  // a create names at most kMaxAssets files: more wants for it are not the server's
  auto& list = by_request_[w.request_id];
  if (list.size() < scenario::kMaxAssets) list.push_back(w);
}

void AssetWants::addDatagram(const void* data, int size) {
  groundsim::asset_want_t w;
  if (decodeMessage(data, size, w, "groundsim.asset_want_t").ok()) add(w);
}

std::vector<groundsim::asset_want_t> AssetWants::take(std::int64_t request_id) {
  std::lock_guard<std::mutex> lk(m_);
  auto it = by_request_.find(request_id);
  if (it == by_request_.end()) return {};
  auto out = std::move(it->second);
  by_request_.erase(it);
  return out;
}

std::size_t sendWantedParts(lcm::LCM& lcm, const std::string& client_id,
                            const std::vector<scenario::Asset>& assets,
                            const std::vector<groundsim::asset_want_t>& wants) {
  std::size_t sent = 0;
  std::uint64_t burst = 0;
  static std::atomic<std::int64_t> seq{0};
  for (const scenario::Asset& a : assets) {
    const int nparts = partsOf(a.ref.size);
    std::vector<int> parts;
    auto w = std::find_if(wants.begin(), wants.end(), [&](const auto& x) { return x.sha256 == a.ref.sha256; });
    if (w != wants.end()) {
      for (int p : w->missing)
        if (p >= 0 && p < nparts) parts.push_back(p);
    } else if (wants.empty()) {
      // no want arrived (lost): the whole file
      for (int p = 0; p < nparts; ++p) parts.push_back(p);
    }
    for (int p : parts) {
      groundsim::asset_part_t m{};
      m.utime = nowMicros();
      m.seq = seq++;
      m.client_id = client_id;
      m.name = a.ref.name;
      m.sha256 = a.ref.sha256;
      m.size = static_cast<std::int64_t>(a.ref.size);
      m.part = p;
      m.nparts = nparts;
      const std::uint64_t begin = static_cast<std::uint64_t>(p) * kPartBytes;
      const std::uint64_t n = std::min(kPartBytes, a.ref.size - begin);
      m.data.assign(a.bytes->begin() + static_cast<std::ptrdiff_t>(begin),
                    a.bytes->begin() + static_cast<std::ptrdiff_t>(begin + n));
      m.nbytes = static_cast<std::int32_t>(n);
      if (lcm.publish(kAssetChannel, &m) != 0)
        throw std::runtime_error("cannot publish part " + std::to_string(p) + " of \"" + a.ref.name + "\"");
      ++sent;
      burst += n;
      if (burst >= kBurstBytes) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        burst = 0;
      }
    }
  }
  return sent;
}

}  // namespace groundsim::net
