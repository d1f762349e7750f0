// A client with the three endpoints of a 3-member etcd keeps working while
// one member is cut off (partition: its requests time out) and when the
// leader's host dies (kill -9 of every process of it). Run in a host of the
// lab by cluster_test.sh, which made the lab and started the members; this
// program partitions, heals and kills through scripts/fleet_lab.sh.
// Then the killed member is started again on its data and must serve the
// writes made while it was dead. Last, this program's own host is cut off
// for 5 s: its membership fences itself within the TTL, etcd expires the
// lease meanwhile, and after the heal the membership registers with a new
// lease; a watch of the servers, reopened after the heal, reports the
// expiry's DELETE before the new registration.
//   cluster_check --lab SCRIPT --name LAB --dir ETCD_DIR --endpoints URL,URL,URL
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "fleet/etcd_client.hpp"
#include "fleet/membership.hpp"
#include "fleet/watch.hpp"

using namespace groundsim::fleet;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

int fail(const std::string& why) {
  std::fprintf(stderr, "cluster_check: FAIL: %s\n", why.c_str());
  return 1;
}

// The index of the leader among endpoints (host = index + 1), -1 when none agrees.
int leaderIndex(const std::vector<std::string>& endpoints) {
  std::map<std::string, int> index_of_member;
  std::string leader;
  for (std::size_t i = 0; i < endpoints.size(); ++i) {
    try {
      EtcdClient one({endpoints[i]}, EtcdClient::Options{300ms});
      auto s = one.call("/v3/maintenance/status", nlohmann::json::object());
      index_of_member[s["header"].value("member_id", std::string())] = static_cast<int>(i);
      leader = s.value("leader", std::string());
    } catch (const std::exception&) {
    }
  }
  auto it = index_of_member.find(leader);
  return it == index_of_member.end() || index_of_member.size() != endpoints.size() ? -1 : it->second;
}

struct Phase {
  int ops = 0, retried = 0;
  double longest = 0, first_ok = -1;
};

// count writes of PREFIX/i, each retried until it lands (at most 10 s each),
// then read back. False when one did not land.
bool writeAll(EtcdClient& c, const std::string& prefix, int count, Phase& p, Clock::time_point from,
              std::string& why) {
  for (int i = 0; i < count; ++i) {
    const auto t0 = Clock::now();
    const std::string n = std::to_string(i);
    std::string key = prefix, value = "v";
    key += n;
    value += n;
    bool done = false;
    while (!done && since(t0) < 10.0) {
      try {
        c.put(key, value);
        done = true;
      } catch (const EtcdError&) {
        ++p.retried;
        std::this_thread::sleep_for(50ms);
      }
    }
    if (!done) {
      why = prefix;
      why += std::to_string(i);
      why += " not written within 10 s";
      return false;
    }
    if (p.first_ok < 0) p.first_ok = since(from);
    p.longest = std::max(p.longest, since(t0));
    ++p.ops;
    std::this_thread::sleep_for(20ms);
  }
  auto kvs = c.range(prefix);
  if (static_cast<int>(kvs.size()) != count) {
    why = prefix + ": " + std::to_string(kvs.size()) + " keys read back, " + std::to_string(count) + " written";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string lab, name, list, dir;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--lab") lab = argv[i + 1];
    else if (a == "--name") name = argv[i + 1];
    else if (a == "--endpoints") list = argv[i + 1];
    else if (a == "--dir") dir = argv[i + 1];
  }
  auto endpoints = EtcdClient::parseEndpoints(list);
  if (lab.empty() || name.empty() || dir.empty() || endpoints.size() != 3) {
    std::fprintf(stderr, "usage: cluster_check --lab SCRIPT --name LAB --dir ETCD_DIR --endpoints URL,URL,URL\n");
    return 2;
  }
  auto labDo = [&](const std::string& what, int index) {
    std::string cmd = "'" + lab + "' " + what + " " + name + " " + std::to_string(index + 1);
    return std::system(cmd.c_str()) == 0;
  };

  // the cluster is up when every member answers and they agree on a leader
  int leader = -1;
  for (auto t0 = Clock::now(); leader < 0 && since(t0) < 30.0;) {
    leader = leaderIndex(endpoints);
    if (leader < 0) std::this_thread::sleep_for(200ms);
  }
  if (leader < 0) return fail("no leader the three members agree on within 30 s");
  std::printf("cluster up, leader: member %d (%s)\n", leader + 1, endpoints[leader].c_str());

  // Phase A: a follower cut off; the client tries it first (its requests time out, 500 ms)
  const int cut = (leader + 1) % 3;
  std::vector<std::string> order = {endpoints[cut], endpoints[leader], endpoints[(leader + 2) % 3]};
  EtcdClient client(order);
  std::atomic<int> lost{0}, registered{0};
  Membership::Options mo;
  mo.id = "check";
  mo.address = "192.0.2.4";
  mo.resume_lease = true;  // etcd extends leases when a new leader is elected
  Membership::Callbacks cb;
  cb.on_lost = [&](const std::string& why) {
    ++lost;
    std::printf("membership lost: %s\n", why.c_str());
  };
  cb.on_registered = [&](std::int64_t) { ++registered; };
  Membership member(client, mo, cb);
  const std::int64_t first_lease = member.leaseId();

  // a watch of everything written, through the same client (its stream
  // starts on the member about to be cut off)
  std::mutex watch_mu;
  std::vector<Kv> seen;
  Watch watch(client, "/lab/", 0, [&](const Watch::Event& e) {
    std::lock_guard lock(watch_mu);
    seen.push_back(e.kv);
  });
  for (auto t0 = Clock::now(); !watch.connected() && since(t0) < 10.0;) std::this_thread::sleep_for(50ms);
  if (!watch.connected()) return fail("the watch did not start");

  std::string why;
  if (!labDo("partition", cut)) return fail("partition failed");
  Phase a;
  const auto cut_at = Clock::now();
  bool ok = writeAll(client, "/lab/a/", 20, a, cut_at, why);
  labDo("heal", cut);
  if (!ok) return fail("with member " + std::to_string(cut + 1) + " cut off: " + why);
  std::printf("member %d cut off: %d writes, %d retried, longest %.2f s, first %.2f s after the cut\n", cut + 1, a.ops,
              a.retried, a.longest, a.first_ok);

  // let the healed member catch up, then find the leader again
  leader = -1;
  for (auto t0 = Clock::now(); leader < 0 && since(t0) < 20.0;) {
    leader = leaderIndex(endpoints);
    if (leader < 0) std::this_thread::sleep_for(200ms);
  }
  if (leader < 0) return fail("no leader after the heal within 20 s");

  // Phase B: the leader's host dies; the client tries it first
  EtcdClient client_b({endpoints[leader], endpoints[(leader + 1) % 3], endpoints[(leader + 2) % 3]});
  if (!writeAll(client_b, "/lab/b0/", 3, a, Clock::now(), why)) return fail("before the kill: " + why);
  const int lost_before = lost.load();
  if (!labDo("kill", leader)) return fail("kill failed");
  const auto killed_at = Clock::now();
  std::printf("killed host %d (the leader)\n", leader + 1);
  Phase b;
  if (!writeAll(client_b, "/lab/b/", 40, b, killed_at, why))
    return fail("after the leader's host was killed: " + why);
  std::printf("leader killed: %d writes, %d retried, longest %.2f s, first %.2f s after the kill\n", b.ops, b.retried,
              b.longest, b.first_ok);
  // what was written before is still there, read through the survivors
  if (client_b.range("/lab/a/").size() != 20) return fail("phase A's keys lost after the kill");
  std::printf("membership over the kill: %s, on_lost %d time(s) during the kill, lease %lld\n",
              member.healthy() ? "healthy" : "not healthy", lost.load() - lost_before,
              static_cast<long long>(member.leaseId()));
  // with two of three members it must hold (or win back) its registration
  for (auto t0 = Clock::now(); !member.healthy() && since(t0) < 10.0;) std::this_thread::sleep_for(100ms);
  if (!member.healthy()) return fail("membership not healthy 10 s after the kill: " + member.lastError());
  if (member.leaseId() != first_lease)
    return fail("the membership's lease was not resumed over the leader's death (etcd extends leases on election)");
  auto kv = client_b.get(Membership::serverKey("/groundsim", "check"));
  if (!kv || kv->lease != member.leaseId()) return fail("membership key missing or not under the current lease");
  // the watch moved with the failures and saw every write once, in order
  std::set<std::string> keys;
  for (auto t0 = Clock::now(); since(t0) < 10.0; std::this_thread::sleep_for(100ms)) {
    std::lock_guard lock(watch_mu);
    keys.clear();
    for (const auto& kv : seen) keys.insert(kv.key);
    if (keys.size() == 63) break;
  }
  {
    std::lock_guard lock(watch_mu);
    if (keys.size() != 63) return fail("the watch saw " + std::to_string(keys.size()) + " of the 63 keys written");
    for (std::size_t i = 1; i < seen.size(); ++i)
      if (seen[i].mod_revision <= seen[i - 1].mod_revision) return fail("the watch repeated or reordered an event");
    std::printf("watch: %zu events for 63 keys in revision order over %d streams\n", seen.size(), watch.streams());
  }
  // the dead member comes back on its data, catches up and serves
  const int dead = leader;
  if (std::system(("'" + lab + "' etcd-start " + name + " '" + dir + "' " + std::to_string(dead + 1)).c_str()) != 0)
    return fail("etcd-start failed");
  const auto restarted = Clock::now();
  int agreed = -1;
  for (; agreed < 0 && since(restarted) < 30.0;) {
    agreed = leaderIndex(endpoints);
    if (agreed < 0) std::this_thread::sleep_for(200ms);
  }
  if (agreed < 0) return fail("the restarted member did not rejoin within 30 s");
  EtcdClient only_back({endpoints[dead]});
  std::size_t caught_up = 0;
  for (auto t0 = Clock::now(); since(t0) < 10.0; std::this_thread::sleep_for(100ms)) {
    try {
      caught_up = only_back.range("/lab/b/").size();
      if (caught_up == 40) break;
    } catch (const EtcdError&) {
    }
  }
  if (caught_up != 40) return fail("the restarted member serves " + std::to_string(caught_up) + " of the 40 writes made while it was dead");
  std::printf("member %d restarted: rejoined %.2f s after its start and serves the writes it missed\n", dead + 1,
              since(restarted));
  // our own host cut off for 5 s
  const int self_host = 4;
  std::mutex servers_mu;
  std::vector<Watch::Event> server_events;
  Watch servers(client_b, Membership::serversPrefix("/groundsim"), 0, [&](const Watch::Event& e) {
    std::lock_guard lock(servers_mu);
    server_events.push_back(e);
  });
  for (auto t0 = Clock::now(); !servers.connected() && since(t0) < 10.0;) std::this_thread::sleep_for(50ms);
  const std::int64_t lease_before = member.leaseId();
  const int lost_before_cut = lost.load(), registered_before_cut = registered.load();
  if (!member.healthy()) return fail("membership not healthy before the self partition");
  if (std::system(("'" + lab + "' partition " + name + " " + std::to_string(self_host)).c_str()) != 0)
    return fail("self partition failed");
  const auto self_cut = Clock::now();
  for (; lost.load() == lost_before_cut && since(self_cut) < member.ttl() + 2.0;) std::this_thread::sleep_for(20ms);
  const double fenced_after = since(self_cut);
  if (lost.load() == lost_before_cut) return fail("no on_lost within TTL + 2 s of the cut");
  if (member.healthy()) return fail("healthy while cut off");
  while (since(self_cut) < 5.0) std::this_thread::sleep_for(50ms);
  std::system(("'" + lab + "' heal " + name + " " + std::to_string(self_host)).c_str());
  const auto healed = Clock::now();
  for (; registered.load() == registered_before_cut && since(healed) < 10.0;) std::this_thread::sleep_for(20ms);
  if (registered.load() == registered_before_cut) return fail("not registered again within 10 s of the heal: " + member.lastError());
  const double back_after = since(healed);
  if (member.leaseId() == lease_before) return fail("the lease outlived a 5 s partition (TTL 2 s)");
  bool deleted = false, put_after = false;
  for (auto t0 = Clock::now(); !(deleted && put_after) && since(t0) < 10.0; std::this_thread::sleep_for(50ms)) {
    std::lock_guard lock(servers_mu);
    deleted = put_after = false;
    for (const auto& e : server_events) {
      if (e.kv.key != Membership::serverKey("/groundsim", "check")) continue;
      if (e.type == Watch::Event::Type::Delete) deleted = true;
      else if (deleted && e.kv.lease == member.leaseId()) put_after = true;
    }
  }
  if (!deleted || !put_after) return fail("the servers' watch did not report the expiry and the new registration");
  std::printf("own host cut off 5 s: on_lost %.2f s after the cut, registered again with a new lease %.2f s after "
              "the heal; the watch saw the DELETE then the new PUT\n", fenced_after, back_after);
  std::printf("cluster_check: OK\n");
  return 0;
}
