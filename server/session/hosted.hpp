// What every hosted session is, whatever it runs (a simulation stepped in
// real time, fast or lockstep; a batch of environments stepped by request):
// an id, an owner token, the owner's last activity, a listing, a stop, and
// the epoch of its owner's claim (docs/fleet.md). The registry
// (registry.hpp) keeps them all in one map; admission, the owner check,
// idle reclamation and failover are written once, against this class.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "clock.hpp"
#include "scheduler.hpp"
#include "types.hpp"

namespace groundsim::session {

class HostedSession : public Task {
 public:
  enum class Kind { Simulation, Vectorised };

  HostedSession(Kind kind, std::string id, std::string token, TimePoint now)
      : kind_(kind), id_(std::move(id)), token_(std::move(token)), last_activity_(now) {}

  Kind kind() const { return kind_; }
  const std::string& id() const { return id_; }
  virtual const std::string& name() const = 0;
  virtual const std::string& scenarioJson() const = 0;
  // Constant-time comparison with the owner's token.
  bool tokenMatches(const std::string& token) const;

  // The client id of the create that made it ("" for a session taken over
  // from a lost owner): what the registry counts against that client's
  // limit (groundsim-server --client-sessions). Set before insertion.
  const std::string& creator() const { return creator_; }
  void setCreator(std::string client) { creator_ = std::move(client); }

  // Owner activity, for idle reclamation (receive thread).
  void touch(TimePoint now);
  double idleSeconds(TimePoint now) const;

  // Receive thread (then wake it): ends the session; it answers `reply`,
  // publishes its last state and takes no more work.
  virtual void stop(std::optional<ReplyTo> reply, std::string reason) = 0;

  // The listing (list, heartbeat, replies), with the owner's idle time.
  SessionInfo info(TimePoint now) const;

  // The owner's claim on the session (0 on a lone server); stamped on
  // everything it publishes from the next message on.
  std::int64_t epoch() const { return epoch_.load(std::memory_order_relaxed); }
  void setEpoch(std::int64_t e) { epoch_.store(e, std::memory_order_relaxed); }

 protected:
  // The kind's own fields of the listing (idle time and epoch are added).
  virtual SessionInfo listing() const = 0;

 private:
  const Kind kind_;
  const std::string id_;
  const std::string token_;
  std::string creator_;
  mutable std::mutex activity_mutex_;
  TimePoint last_activity_;
  std::atomic<std::int64_t> epoch_{0};
};

// The refusal of a request naming a session it may not use: unknown, no
// token, wrong token. The one wording of the owner check ("" = allowed).
struct OwnerCheck {
  ErrorCode code = ErrorCode::None;
  std::string why;
  explicit operator bool() const { return code == ErrorCode::None; }
};
OwnerCheck checkOwner(const HostedSession* s, const std::string& session_id, const std::string& token);

}  // namespace groundsim::session
