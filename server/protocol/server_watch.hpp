// A client's view of the server's heartbeat (server_status_t on
// GROUNDSIM_STATUS, every kHeartbeatPeriod): whether the server is still
// there, and what it last said about a session. A client that hears no
// heartbeat for kHeartbeatTimeout (counted from its start when it has heard
// none yet) treats the server as gone instead of waiting forever.
//
// A fleet (docs/fleet.md) is many servers on one bus, each heartbeating its
// own sessions: the watch keeps every server's last heartbeat, and a
// session is as the freshest listing of its highest epoch says. A server's
// listing is kept for kFleetRetention after its last heartbeat, so that a
// session whose host died stays known while a standby takes it over.
#pragma once

#include <chrono>
#include <map>
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
  // Seconds since server_id's last heartbeat (a fleet: one server's
  // silence while the others beat); since the start when never heard.
  double silenceOf(const std::string& server_id, Clock::time_point now = Clock::now()) const;
  // How long server_id may be silent before it is taken for dead: 4 of its
  // heartbeat periods as measured (a fleet beats every 0.25 s), at least
  // 1 s, at most the watch's timeout, which is also the answer until 3 of
  // its beats were heard.
  double timeoutOf(const std::string& server_id) const;
  // Seconds since the last heartbeat (or since the start, before the first).
  double silence(Clock::time_point now = Clock::now()) const;
  long long heartbeats() const { return count_; }
  // Heartbeats of the least heard server among those heard lately: "two
  // rounds later" means every server (a session's owner too) has beaten
  // twice, which a count of all heartbeats does not say in a fleet.
  long long rounds() const;
  // How long a silent server's listing is kept (a failover's length, docs/fleet.md).
  static constexpr double kFleetRetention = 6.0;
  static constexpr std::size_t kMaxServers = 1024;  // servers kept at once
  // The session as the last heartbeats listed it; nothing if none did.
  std::optional<groundsim::session_info_t> session(const std::string& id) const;
  // Every session the last heartbeats listed (running and recently ended), once each.
  std::vector<groundsim::session_info_t> sessions() const;
  // "no heartbeat from groundsim-server for 3.0 s on URL (killed or unreachable)"
  std::string lostMessage(const std::string& url, Clock::time_point now = Clock::now()) const;

 private:
  void onStatus(const lcm::ReceiveBuffer* rbuf, const std::string& channel);

  lcm::LCM& lcm_;
  lcm::Subscription* sub_ = nullptr;
  double timeout_s_;
  Clock::time_point start_, since_;
  long long count_ = 0;
  struct Beat {
    groundsim::server_status_t status;
    Clock::time_point at;
    long long beats = 0;
    double period = 0;  // s between its beats, smoothed; 0: not known yet
  };
  std::map<std::string, Beat> last_;  // by server_id
};

}  // namespace groundsim::net
