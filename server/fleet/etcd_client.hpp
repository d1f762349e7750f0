// A synchronous, thread-safe client of etcd's v3 JSON gateway (etcd 3.4:
// POST /v3/kv/range, /v3/kv/put, /v3/kv/deleterange, /v3/kv/txn,
// /v3/lease/grant, /v3/lease/keepalive, /v3/lease/revoke,
// /v3/lease/timetolive, /v3/watch) over
// HTTP/1.1 with Boost.Beast. Keys and values are bytes (base64 on the wire);
// 64-bit numbers travel as JSON strings and absent fields mean 0 (proto3).
//
// Several endpoints: a call goes to the endpoint that answered last and, on a
// connection failure, a timeout or an etcd "unavailable" answer, to the next
// one; every attempt is bounded by Options::attempt_timeout, so a call takes
// at most endpoints x attempt_timeout. An answer that is an error of the
// request (a bad lease, a malformed request) is not retried elsewhere.
// Failures are EtcdError, naming the endpoint and the reason.
//
// A retried write is at least once: a put whose answer was lost may have been
// applied before the next endpoint applies it again. createIfAbsent() tells
// its own earlier success (same value and lease) from another creator.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace groundsim::fleet {

// One key as etcd stores it.
struct Kv {
  std::string key, value;
  std::int64_t create_revision = 0;  // revision of the put that created it
  std::int64_t mod_revision = 0;     // revision of its last change
  std::int64_t version = 0;          // changes since creation (1 = just created)
  std::int64_t lease = 0;            // 0: none
};

struct LeaseGrant {
  std::int64_t id = 0;
  std::int64_t ttl_s = 0;  // granted (etcd raises a smaller ask to its minimum, 2 s here)
};

struct LeaseInfo {
  std::int64_t id = 0;
  std::int64_t ttl_s = -1;          // remaining, whole seconds (0: under a second left); -1: gone
  std::int64_t granted_ttl_s = 0;
  std::vector<std::string> keys;    // bound to it (when asked for)
  bool alive() const { return ttl_s >= 0; }
};

class EtcdError : public std::runtime_error {
 public:
  // transport: no answer (connection refused, timeout, closed); otherwise
  // etcd answered with an error (grpc_code is its gRPC status code).
  EtcdError(std::string endpoint, std::string reason, bool transport, int grpc_code = -1);
  const std::string& endpoint() const { return endpoint_; }
  const std::string& reason() const { return reason_; }
  bool transport() const { return transport_; }
  int grpcCode() const { return grpc_code_; }

 private:
  std::string endpoint_, reason_;
  bool transport_;
  int grpc_code_;
};

// Conditions and operations of a transaction (etcd's Compare and RequestOp).
struct Compare {
  enum class Target { Version, Create, Mod, Value, Lease };
  enum class Result { Equal, Greater, Less, NotEqual };
  std::string key;
  Target target = Target::Version;
  Result result = Result::Equal;
  std::int64_t number = 0;  // Version, Create, Mod, Lease
  std::string value;        // Value

  static Compare version(std::string key, Result r, std::int64_t v) { return {std::move(key), Target::Version, r, v, {}}; }
  static Compare modRevision(std::string key, Result r, std::int64_t v) { return {std::move(key), Target::Mod, r, v, {}}; }
  static Compare createRevision(std::string key, Result r, std::int64_t v) { return {std::move(key), Target::Create, r, v, {}}; }
  static Compare leaseIs(std::string key, Result r, std::int64_t v) { return {std::move(key), Target::Lease, r, v, {}}; }
  static Compare valueIs(std::string key, Result r, std::string v) { return {std::move(key), Target::Value, r, 0, std::move(v)}; }
};

struct Op {
  enum class Kind { Put, Get, Delete, GetPrefix, DeletePrefix };
  Kind kind = Kind::Get;
  std::string key, value;
  std::int64_t lease = 0;

  static Op put(std::string key, std::string value, std::int64_t lease = 0) {
    return {Kind::Put, std::move(key), std::move(value), lease};
  }
  static Op get(std::string key) { return {Kind::Get, std::move(key), {}, 0}; }
  static Op del(std::string key) { return {Kind::Delete, std::move(key), {}, 0}; }
  static Op getPrefix(std::string prefix) { return {Kind::GetPrefix, std::move(prefix), {}, 0}; }
  static Op delPrefix(std::string prefix) { return {Kind::DeletePrefix, std::move(prefix), {}, 0}; }
};

struct TxnResult {
  bool succeeded = false;
  std::int64_t revision = 0;           // the store's revision after the transaction
  std::vector<std::vector<Kv>> reads;  // per Get/GetPrefix op of the branch taken, in order
};

class EtcdClient {
 public:
  struct Options {
    std::chrono::milliseconds attempt_timeout{500};  // one endpoint: connect + request + answer
  };

  // endpoints: "http://host:port" (or "host:port"); at least one.
  explicit EtcdClient(std::vector<std::string> endpoints);
  EtcdClient(std::vector<std::string> endpoints, Options options);
  // "http://a:2379,http://b:2379" -> {"http://a:2379", "http://b:2379"}
  static std::vector<std::string> parseEndpoints(const std::string& comma_separated);

  const std::vector<std::string>& endpoints() const { return endpoints_; }
  const Options& options() const { return options_; }

  LeaseGrant leaseGrant(std::int64_t ttl_s);
  // One renewal; the TTL remaining after it, 0 when the lease has expired (or never existed).
  std::int64_t leaseKeepAliveOnce(std::int64_t id);
  // Ends the lease and deletes its keys; a lease already gone is not an error.
  void leaseRevoke(std::int64_t id);
  // What is left of a lease, without renewing it (e.g. another server's).
  LeaseInfo leaseTimeToLive(std::int64_t id, bool with_keys = false);

  // The revision of the store after the write.
  std::int64_t put(const std::string& key, const std::string& value, std::int64_t lease = 0);
  // serializable: the member's own copy, with no quorum round (it may lag
  // the leader by what it has not applied yet); else linearizable.
  std::optional<Kv> get(const std::string& key, bool serializable = false);
  // Every key starting with prefix, in key order ("" = every key).
  std::vector<Kv> range(const std::string& prefix, bool serializable = false);
  // The number of keys deleted (0 or 1).
  std::int64_t del(const std::string& key);
  std::int64_t delPrefix(const std::string& prefix);

  // Creates key only if it does not exist (txn: version == 0). False: it exists.
  bool createIfAbsent(const std::string& key, const std::string& value, std::int64_t lease = 0);
  // Creates key if it does not exist, in one transaction that reads it
  // otherwise: the value the store holds after it (value when created).
  std::string createOrRead(const std::string& key, const std::string& value, std::int64_t lease = 0);
  // Writes key only if its mod_revision is still expected_mod_revision
  // (0: only if absent). False: it changed (or vanished).
  bool compareAndSwap(const std::string& key, std::int64_t expected_mod_revision, const std::string& value,
                      std::int64_t lease = 0);
  // Deletes key only if its mod_revision is still mod_revision.
  bool deleteIf(const std::string& key, std::int64_t mod_revision);
  TxnResult txn(const std::vector<Compare>& compare, const std::vector<Op>& success,
                const std::vector<Op>& failure = {});

  // The store's current revision.
  std::int64_t revision();

  // One request to the gateway, with the endpoint failover of every call: the
  // answer's JSON (an error answer throws). For what the typed calls lack.
  nlohmann::json call(const std::string& path, const nlohmann::json& body);

  static std::string base64Encode(const std::string& bytes);
  static std::string base64Decode(const std::string& text);  // throws std::invalid_argument
  // The smallest key after every key starting with prefix; "\0" (etcd: no end)
  // when there is none ("" or all 0xff).
  static std::string prefixEnd(const std::string& prefix);

 private:
  std::vector<std::string> endpoints_;
  Options options_;
  std::atomic<std::size_t> preferred_{0};
};

}  // namespace groundsim::fleet
