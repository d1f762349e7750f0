// A server's membership of a fleet (docs/fleet.md, "Membership (etcd)"): a
// lease of TTL seconds, the key PREFIX/servers/<id> bound to it holding
//   {"id", "address", "build", "capacity": {"sessions_free", "max_sessions",
//    "workers", "load"}, "draining", "started_utime"}
// renewed from its own thread every TTL/3, and a view of every member
// (a range of PREFIX/servers/ at least every view_period).
//
// Registration is a create-if-absent: a second server with the same id is
// refused (MembershipError) while the first's lease lives; after it lapses
// the id is free again. When no renewal succeeded for longer than the TTL
// (counted from the sending of the last renewal that succeeded, so never
// after etcd's own expiry) or etcd says the lease is gone, the membership is
// lost: on_lost is called once, healthy() is false and the owner stops
// publishing (self-fencing). Its thread then revokes the old lease (its keys
// go with it, if they are still there), grants a new one and registers again
// as soon as etcd answers; on_registered gives the new lease. With
// Options::resume_lease it first renews the old lease: when etcd still holds
// it (etcd extends every lease when a new leader is elected or a member
// restarts, so an etcd outage or a leader's death need not have expired it)
// and the key is still under it, the member resumes it, keys and all, and
// on_registered gives the same lease: nothing bound to it can have been
// taken by another server meanwhile, since that needs the key gone.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "fleet/etcd_client.hpp"

namespace groundsim::fleet {

// The id is taken by a live server (or the registration is refused for another reason of the fleet's).
class MembershipError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Member {
  std::string id;
  nlohmann::json info;  // the registered value (null when it is not JSON)
  std::int64_t lease = 0;
  std::int64_t mod_revision = 0;
};

class Membership {
 public:
  struct Options {
    std::string id;       // unique in the fleet: [A-Za-z0-9._-], 1-64 characters
    std::string address;  // how the others reach this server (free text: "192.0.2.1", "host:port")
    std::string build;    // version and build of the server
    std::int64_t ttl_s = 2;              // etcd grants at least 2 s with its default timings
    std::string prefix = "/groundsim";   // the fleet's key space
    std::chrono::milliseconds view_period{250};
    bool resume_lease = false;  // after a loss, take the old lease back if etcd still holds it
    // {"sessions_free", "max_sessions", "workers", "load"} (update() replaces it)
    nlohmann::json capacity = {{"sessions_free", 0}, {"max_sessions", 0}, {"workers", 0}, {"load", 0.0}};
  };
  // Called from the membership's threads, never under its lock; they may
  // read the membership (healthy(), members()) but not leave() or abandon().
  struct Callbacks {
    std::function<void(const std::string& reason)> on_lost;      // once per loss
    std::function<void(std::int64_t lease)> on_registered;       // registered again after a loss (not the first
                                                                 // time); the lost lease when resumed
    std::function<void(const std::vector<Member>&)> on_members;  // the view changed (ids, leases, revisions)
  };

  // Registers (throws MembershipError when the id is taken, EtcdError when no
  // endpoint answers) and starts the thread. client outlives the membership.
  Membership(EtcdClient& client, Options options, Callbacks callbacks = {});
  ~Membership();  // leave(): the key goes at once
  Membership(const Membership&) = delete;
  Membership& operator=(const Membership&) = delete;

  // Stops the thread and revokes the lease: the key is gone at once.
  void leave();
  // Stops the thread without revoking: the key lapses with the lease, as
  // when the process dies (tests; a server that must not touch etcd again).
  void abandon();

  // Replaces the capacity and publishes it (from the thread, at once).
  void update(const nlohmann::json& capacity);
  void setDraining(bool draining);

  // Every member's registration as last read (this server's too).
  std::vector<Member> members() const;
  std::optional<Member> member(const std::string& id) const;
  // The lease held now; 0 while lost.
  std::int64_t leaseId() const;
  std::int64_t ttl() const { return ttl_s_.load(); }  // as granted
  // Registered and renewed within the TTL.
  bool healthy() const;
  // Why the last etcd call failed ("" when the last one succeeded).
  std::string lastError() const;
  const std::string& id() const { return options_.id; }
  std::string key() const { return serverKey(options_.prefix, options_.id); }
  nlohmann::json value() const;

  static std::string serverKey(const std::string& prefix, const std::string& id);
  static std::string serversPrefix(const std::string& prefix) { return prefix + "/servers/"; }

 private:
  using Clock = std::chrono::steady_clock;
  void run();
  void fence();
  bool registerOnce(std::string* why_not);
  bool keepAlive();  // false: no answer
  void publish();
  void refreshView();
  void markLost(const std::string& reason);
  void setError(const std::string& e);
  void stopThreads();

  EtcdClient& client_;
  Options options_;
  Callbacks callbacks_;
  std::int64_t started_utime_ = 0;
  std::atomic<std::int64_t> ttl_s_{0};

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  bool registered_ = false;      // holds lease_, renewed within the TTL as far as the fence knows
  bool dirty_ = false;           // capacity or draining changed since the last publish
  bool republish_ = false;       // a publish failed: again with the next renewal
  bool draining_ = false;
  std::int64_t lease_ = 0, old_lease_ = 0;
  Clock::time_point renewed_sent_;  // the sending of the last renewal that succeeded
  nlohmann::json capacity_;
  std::vector<Member> members_;
  std::string last_error_;
  std::thread worker_, fencer_;
};

}  // namespace groundsim::fleet
