// A client's view of the server's heartbeat (server_status_t on
// GROUNDSIM_STATUS, every kHeartbeatPeriod): whether the server is still
// there, and what it last said about a session. A client that hears no
// heartbeat for kHeartbeatTimeout (counted from its start when it has heard
// none yet) treats the server as gone instead of waiting forever.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/server_status_t.hpp>
#include <groundsim/session_info_t.hpp>

#include "limits.hpp"

namespace groundsim::net {

class ServerWatch {
 public:
  using Clock = std::chrono::steady_clock;

  // Subscribes on lcm; heartbeats arrive through lcm.handle*() like any message.
  explicit ServerWatch(lcm::LCM& lcm, double timeout_s = kHeartbeatTimeout);
  ~ServerWatch();
  ServerWatch(const ServerWatch&) = delete;
  ServerWatch& operator=(const ServerWatch&) = delete;

  // No heartbeat for the timeout.
  bool lost(Clock::time_point now = Clock::now()) const;
  // Seconds since the last heartbeat (or since the start, before the first).
  double silence(Clock::time_point now = Clock::now()) const;
  long long heartbeats() const { return count_; }
  // The session as the last heartbeat listed it; nothing if it was not listed.
  std::optional<groundsim::session_info_t> session(const std::string& id) const;
  // Every session the last heartbeat listed (running and recently ended).
  std::vector<groundsim::session_info_t> sessions() const;
  // "no heartbeat from groundsim-server for 3.0 s on URL (killed or unreachable)"
  std::string lostMessage(const std::string& url, Clock::time_point now = Clock::now()) const;

 private:
  void onStatus(const lcm::ReceiveBuffer* rbuf, const std::string& channel);

  lcm::LCM& lcm_;
  lcm::Subscription* sub_ = nullptr;
  double timeout_s_;
  Clock::time_point since_;
  long long count_ = 0;
  std::optional<groundsim::server_status_t> last_;
};

}  // namespace groundsim::net
