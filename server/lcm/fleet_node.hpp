// A server's part in a fleet (docs/fleet.md): membership on etcd
// (fleet::Membership), the placement of creates heard on the shared bus,
// ownership of sessions with epochs as fencing tokens, the standby copies of
// other servers' sessions (their replicas and applied-command logs) and
// their resumption here when their owner's lease lapses, self-fencing when
// this server cannot renew its own lease, and drain.
//
// etcd keys under the prefix (default /groundsim):
//   servers/<id>   the membership (fleet/membership.hpp), bound to its lease
//   owners/<sid>   {"server", "epoch"[, "create"]}: who owns session sid (and
//                  the create that made it), bound to the
//                  owner's lease (it vanishes with the owner)
//   epochs/<sid>   the last epoch given for sid (no lease: it outlives owners)
//   creates/<client>/<request>  the server a create was placed on (10 s lease):
//                  the first server to hear it places it and writes this
//                  key; every server reads it; the one it names builds
//                  the session
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "fleet/etcd_client.hpp"
#include "fleet/membership.hpp"
#include "session/ownership.hpp"
#include "session/service.hpp"
#include "standby_log.hpp"

namespace groundsim::net {

struct FleetOptions {
  std::vector<std::string> endpoints;  // etcd
  std::string server_id;               // unique in the fleet
  std::string address;                 // how others reach this server (informational)
  std::string build;
  std::string placement = "spread";    // "spread" balances, "packed" fills a server before the next
  std::int64_t ttl_s = 2;              // the membership lease (etcd's minimum: 2)
  std::string prefix = "/groundsim";
  std::chrono::milliseconds scan_period{250};   // owners' view and failover checks
  std::chrono::milliseconds rank_delay{200};    // failover: the standby ranked k claims after k x this
  std::chrono::milliseconds heartbeat_period{250};  // every server's; silent for 3.5 of them: not placed on
  std::size_t max_standby_sessions = 4096;      // replicas kept of other servers' sessions
  std::size_t max_log_entries = 1 << 16;        // applied entries kept per standby session (the oldest go:
                                                //   one snapshot interval's worth is what a takeover replays)
};

class FleetNode final : public session::Ownership {
 public:
  // Joins the fleet (throws fleet::MembershipError when the id is live
  // elsewhere, fleet::EtcdError when etcd cannot be reached). `out`
  // publishes replicas (the LcmServer); both outlive the node.
  FleetNode(FleetOptions options, session::SessionService& service, session::Output& out);
  ~FleetNode() override;

  // ---- session::Ownership (workers; the receive thread) ----
  std::int64_t claim(const std::string& id, const std::string& placement) override;
  void release(const std::string& id) override;

  // ---- the receive thread ----
  // A create heard on the bus: `take` runs later on the node's thread if
  // the create's placement (creates/<client>/<request>) names this server;
  // `refuse` if it could not be placed for kCreateRetry (etcd away) and
  // this server's refusal is the placement written (giveUp).
  void onCreate(const std::string& client_id, std::int64_t request_id, std::function<void()> take,
                std::function<void(const std::string&)> refuse);
  // Whether this server answers a request naming this session now: it
  // hosts it. When no server is known to own it (a session created a
  // moment ago may not be in the owners' view yet), `unknown` runs on the
  // node's thread after two scans if still nobody owns it and this server
  // answers for the fleet (the service then says it is unknown).
  bool answers(const std::string& session_id, std::function<void()> unknown);
  // The one server that answers what no owner answers (OP_LIST, unknown sessions).
  bool isAnswerer() const;
  void onReplica(const session::Replica& r, const std::string& server_id);
  void onApplied(const session::Applied& a);
  // The head of another server's state (convert.hpp, peekState): how far
  // the owner of a kept session has published.
  void onState(const std::string& session_id, std::int64_t seq, std::int64_t tick, std::int64_t epoch);
  // Another server's heartbeat listing (for OP_LIST and the heartbeat).
  void onListing(const std::string& server_id, std::vector<session::SessionInfo> sessions);
  // Every session of the fleet: this server's and the others' last heartbeats.
  std::vector<session::SessionInfo> fleetSessions(std::vector<session::SessionInfo> own) const;

  // Before the node runs: how a standby asks the owner again for frames
  // (and the applied entries kept with them) it missed, by seq range; the
  // answers come back through onApplied.
  using AskAgain = std::function<void(const std::string& session_id, std::int64_t from_frame, std::int64_t to_frame)>;
  void setAskAgain(AskAgain ask);

  // ---- any thread ----
  // False while fenced (the lease could not be renewed) and for sessions
  // another server took over: their messages must not be published.
  bool mayPublish(const std::string& session_id) const;
  bool fenced() const { return fenced_.load(); }
  // Other servers' sessions this server keeps a replica of (their standby).
  std::size_t standbyCount() const {
    std::lock_guard<std::mutex> lk(mutex_);
    return standby_.size();
  }
  // Not disowned: as far as this server knows, the session is still its own.
  bool holds(const std::string& session_id) const;
  // The heartbeat's figures as capacity in the membership.
  void updateCapacity(const session::ServiceStatus& st);
  // Takes no new session and hands every session over to the others (their
  // standbys resume them); returns when done or after `timeout`.
  void drain(std::chrono::milliseconds timeout);
  bool draining() const { return draining_.load(); }
  const std::string& serverId() const { return options_.server_id; }
  fleet::Membership& membership() { return *membership_; }

 private:
  struct Standby {
    std::string owner;
    std::int64_t epoch = 0;
    std::optional<session::Replica> scenario, snapshot;
    StandbyLog log;  // from the snapshot's applied_seq on
    std::set<std::int64_t> gaps_seen;  // first seqs of the gaps found at the last scan
    std::int64_t heard_seq = -1, heard_tick = -1;  // the owner's newest state heard (this epoch's)
    std::chrono::steady_clock::time_point absent_since{};  // owners/<sid> missing since (zero: present)
  };
  using Clock = std::chrono::steady_clock;

  void run();  // the node's thread: delayed creates, releases, scans
  void scan();
  void tryTakeOver(const std::string& sid, Standby copy);
  // an owners/ key naming this server for a session it does not host
  struct Stray {
    std::string session_id, value;
    std::int64_t epoch = 0, lease = 0;
    std::optional<Standby> standby;  // this server's replicas of it, if any
  };
  void settleStray(Stray k);
  // hosts the session from a standby's replicas at `epoch`, its owners/ key `value` written
  void resume(const std::string& sid, Standby s, std::int64_t epoch, const std::string& value);
  void onRegistered(std::int64_t lease);
  // Live members that take sessions, in placement order for these loads.
  std::vector<std::string> ranked(const std::map<std::string, int>& loads) const;
  std::string key(const std::string& kind, const std::string& rest) const;
  std::int64_t claimsLease();

  FleetOptions options_;
  AskAgain ask_again_;  // under mutex_ (set while the node's thread runs)
  session::SessionService& service_;
  session::Output& out_;
  fleet::EtcdClient client_;
  std::unique_ptr<fleet::Membership> membership_;
  std::atomic<bool> fenced_{false}, draining_{false}, stopping_{false};

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  struct Pending {
    std::string client_id;
    std::int64_t request_id = 0;
    std::function<void()> take;
    std::function<void(const std::string&)> refuse;
    Clock::time_point at;  // heard; placement is tried again after an etcd error for kCreateRetry
  };
  static constexpr std::chrono::seconds kCreateRetry{10};
  // then, until the create is kGiveUpBy old, every server tries to refuse it (giveUp)
  static constexpr std::chrono::seconds kGiveUpBy{60};
  static constexpr const char* kNowhere = "-";  // a creates/ value "-<server>": refused by that server
  static constexpr std::size_t kMaxPendingCreates = 4096;
  static constexpr std::size_t kMaxAsksPerScan = 64;  // gap repair: a flood of made-up gaps stays bounded
  bool retry_ = false;  // under mutex_: the last pass failed on etcd, wait a scan period
  void place(const Pending& p);
  void giveUp(const Pending& p);
  bool mayClaim() const;  // claim() would not throw: a lease held, not fenced, not draining
  // Sessions per server: owners' keys and recent placements (both count a
  // session being built, for every server alike, so the order is fair).
  std::map<std::string, int> loads();
  // The same counts read from etcd (owners/ and creates/): fresh, but two
  // round trips; taken when the local view puts a server near full.
  std::map<std::string, int> loadsFromEtcd();
  bool nearFull(const std::map<std::string, int>& loads, const std::string& server) const;
  std::vector<Pending> creates_;
  std::vector<std::string> releases_;
  struct Unknown {
    std::string session_id;
    Clock::time_point due;
    std::function<void()> answer;
  };
  std::vector<Unknown> unknowns_;  // at most kMaxUnknowns: a flood of made-up ids is not all answered
  static constexpr std::size_t kMaxUnknowns = 1024;
  std::map<std::string, std::string> owners_;        // sid -> owning server, as last scanned
  std::set<std::string> realised_;  // creates/ keys whose session is in owners_ (its claim names the create)
  // members at the last scan and their leases (the node's thread): a
  // member back with its id between two views has a new lease
  std::map<std::string, std::int64_t> members_seen_;
  struct Placed {
    std::string server;
    Clock::time_point at;
  };
  std::map<std::string, Placed> placed_;  // creates/ keys this server wrote or read, for kCreateRetry
  std::map<std::string, std::int64_t> my_epochs_;    // sessions this server claimed, and their epochs
  std::map<std::string, std::string> my_values_;     // their owners/ values as written here (compared by value)
  std::set<std::string> disowned_;
  std::set<std::string> claiming_;  // ids whose claim() is under way (its key may be in etcd already)
  std::map<std::string, Standby> standby_;
  struct Listing { std::vector<session::SessionInfo> sessions; Clock::time_point at; };
  std::map<std::string, Listing> listings_;  // other servers' last heartbeats, silent ones dropped after 6 s
  std::map<std::string, Clock::time_point> beats_;  // when each was last heard, kept 60 s (placement)
  int capacity_free_ = -1;  // what was last written to etcd (updateCapacity)
  double capacity_load_ = -1;
  Clock::time_point capacity_at_{};
  static constexpr std::size_t kMaxServers = 1024;
  std::int64_t claims_lease_ = 0;
  Clock::time_point claims_lease_at_{};
  std::thread thread_;
};

}  // namespace groundsim::net
