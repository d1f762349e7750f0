// FleetNode's placement (fleet_node.hpp): every server hears a create, and
// the first to write its creates/ key names the server that takes it, by
// the loads this server knows (etcd's near a server's limit) and the
// placement policy (spread or packed).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fleet_node.hpp"
#include "fleet_owners.hpp"

namespace groundsim::net {

using fleet_owners::Owner;
using fleet_owners::ownerOf;

void FleetNode::onCreate(const std::string& client_id, std::int64_t request_id, std::function<void()> take,
                         std::function<void(const std::string&)> refuse) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    // kept for retries while etcd is away: a flood of creates is not all kept (their clients time out)
    if (creates_.size() >= kMaxPendingCreates) return;
    creates_.push_back(Pending{client_id, request_id, std::move(take), std::move(refuse), Clock::now()});
  }
  wake_.notify_all();
}

std::int64_t FleetNode::claimsLease() {
  const auto now = Clock::now();
  if (claims_lease_ == 0 || now - claims_lease_at_ > std::chrono::seconds(5)) {
    claims_lease_ = client_.leaseGrant(10).id;
    claims_lease_at_ = now;
  }
  return claims_lease_;
}

// Sessions per server, from what this server knows without asking etcd (a
// create's path holds no etcd read for it): the owners as last scanned
// (every 250 ms) and the placements it made or read since (every server
// hears every create, so it sees every placement) whose session is not among
// them yet. A session's owners/ value names the create that made it, so a
// burst of creates is counted before its sessions exist, and each once
// however long its clients take.
std::map<std::string, int> FleetNode::loads() {
  const auto now = Clock::now();
  std::map<std::string, int> n;
  std::lock_guard<std::mutex> lk(mutex_);
  std::erase_if(placed_, [&](const auto& kv) { return now - kv.second.at > kCreateRetry; });
  for (const auto& [sid, server] : owners_) ++n[server];
  for (const auto& [k, p] : placed_)
    if (!realised_.count(k)) ++n[p.server];
  return n;
}

std::map<std::string, int> FleetNode::loadsFromEtcd() {
  std::map<std::string, int> n;
  std::set<std::string> realised;
  for (const fleet::Kv& kv : client_.range(options_.prefix + "/owners/", true)) {
    const Owner o = ownerOf(kv.value);
    ++n[o.server];
    if (!o.placement.empty()) realised.insert(key("creates", o.placement));
  }
  for (const fleet::Kv& kv : client_.range(options_.prefix + "/creates/", true))
    if (!realised.count(kv.key)) ++n[kv.value];
  return n;
}

// The local view lags etcd by up to a scan period: near a server's limit it
// may miss the last placements' claims, and a create placed on a full server
// is refused. Within a few sessions of it, the counts are read from etcd.
bool FleetNode::nearFull(const std::map<std::string, int>& loads, const std::string& server) const {
  for (const fleet::Member& m : membership_->members()) {
    if (m.id != server || !m.info.is_object()) continue;
    const double max = m.info.value("capacity", nlohmann::json::object()).value("max_sessions", 0.0);
    const auto it = loads.find(server);
    return it != loads.end() && it->second >= max - 4;
  }
  return false;
}

std::vector<std::string> FleetNode::ranked(const std::map<std::string, int>& loads) const {
  struct Row { std::string id; double used; };
  std::vector<Row> rows;
  const auto now = Clock::now();
  std::map<std::string, Clock::time_point> beats;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    beats = beats_;
  }
  // as a client judges a server (protocol/server_watch.hpp): silent for 3.5 periods
  const auto silent = options_.heartbeat_period * 7 / 2;
  for (const fleet::Member& m : membership_->members()) {
    const nlohmann::json& info = m.info;
    if (!info.is_object() || info.value("draining", false)) continue;
    // a member whose heartbeat stopped (dead, its lease not lapsed yet) takes
    // nothing, nor this server while fenced (it could not claim the session)
    if (m.id == options_.server_id && !mayClaim()) continue;
    const auto beat = beats.find(m.id);
    if (m.id != options_.server_id && beat != beats.end() && now - beat->second > silent) continue;
    const nlohmann::json cap = info.value("capacity", nlohmann::json::object());
    const double max = cap.value("max_sessions", 0.0);
    const auto it = loads.find(m.id);
    const double count = it == loads.end() ? 0.0 : it->second;
    if (max <= 0 || count >= max) continue;  // full
    rows.push_back(Row{m.id, count / max});
  }
  const bool packed = options_.placement == "packed";
  std::sort(rows.begin(), rows.end(), [&](const Row& a, const Row& b) {
    if (a.used != b.used) return packed ? a.used > b.used : a.used < b.used;
    return a.id < b.id;
  });
  std::vector<std::string> out;
  for (const Row& r : rows) out.push_back(r.id);
  return out;
}

// Every server hears a create; the first to write creates/<client>/<request>
// names the server that takes it. Create to first state is what a player
// waits for, so the path holds one serializable read (a member's own copy,
// no quorum round: a stale "absent" only leads to the transaction, which
// decides) and the transaction; the loads are this server's own view
// (etcd's only near a server's limit).
void FleetNode::place(const Pending& p) {
  const std::string k = key("creates", p.client_id + "/" + std::to_string(p.request_id));
  std::string named;
  if (std::optional<fleet::Kv> placed = client_.get(k, true)) {
    named = placed->value;
  } else {
    const std::map<std::string, int> local = loads();
    std::vector<std::string> order = ranked(local);
    if (!order.empty() && nearFull(local, order.front())) order = ranked(loadsFromEtcd());
    if (order.empty()) {
      if (isAnswerer()) p.take();  // nobody takes sessions: this one refuses it (full, draining)
      return;
    }
    named = client_.createOrRead(k, order.front(), claimsLease());
  }
  {
    std::lock_guard<std::mutex> lk(mutex_);
    if (placed_.size() < kMaxPendingCreates) placed_[k] = Placed{named, Clock::now()};
  }
  if (named == options_.server_id) p.take();
}

// A create no server could place for kCreateRetry (etcd did not answer):
// every server stops placing it and tries to refuse it instead, by writing
// its placement as "nowhere (refused by this server)" in the same
// create-if-absent every placement uses. The one write that lands decides:
// a placement still on its way either won (its server takes the create, no
// refusal) or reads the refusal (and takes nothing), and of the servers
// refusing only the one whose refusal was written answers. A client hears
// exactly one answer, or none while etcd stays away.
void FleetNode::giveUp(const Pending& p) {
  const std::string k = key("creates", p.client_id + "/" + std::to_string(p.request_id));
  const std::string mine = std::string(kNowhere) + options_.server_id;
  const std::string named = client_.createOrRead(k, mine, claimsLease());
  if (named == options_.server_id) return p.take();
  if (named != mine) return;
  std::fprintf(stderr, "groundsim-server: fleet: create %s/%lld refused: not placed in %lld s\n",
               p.client_id.c_str(), static_cast<long long>(p.request_id),
               static_cast<long long>(kCreateRetry.count()));
  p.refuse("the fleet could not place the create in " + std::to_string(kCreateRetry.count()) +
           " s (its etcd did not answer): nothing was created; create again");
}

}  // namespace groundsim::net
