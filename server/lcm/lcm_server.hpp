// The LCM adapter of groundsim-server: one receive thread (the only caller
// of lcm::LCM::handle) decodes requests and drive commands and hands them to
// the SessionService; replies, states and events come back through
// session::Output from any thread and are encoded and published here.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include <lcm/lcm-cpp.hpp>

#include "resend_ring.hpp"
#include "session/types.hpp"
#include "session/service.hpp"

namespace groundsim {
class resend_t;
}

namespace groundsim::net {

class FleetNode;

class LcmServer final : public session::Output {
 public:
  // Throws std::runtime_error when the URL cannot be opened.
  LcmServer(const std::string& url, const session::ServiceConfig& cfg, bool verbose);
  ~LcmServer() override;

  // Receives until *stop becomes true, then stops every session (each
  // publishes a final frame with status stopped).
  void run(const std::atomic<bool>& stop);

  // Never throw: a message that cannot be encoded or sent is counted and logged.
  void publishState(const session::Frame& f) override;
  void publishReply(const session::Reply& r) override;
  void publishEvent(const session::Event& e) override;
  // Split into parts of at most net::kMaxVecPartBytes, each published on its own.
  void publishVecReply(const session::VecReply& r) override;
  void publishAssetWant(const session::AssetWant& w) override;
  // On GROUNDSIM_APPLIED_<session>, kept in the resend ring with the frame published next.
  void publishApplied(const session::Applied& a) override;
  // On GROUNDSIM_REPLICA_<session> (fleets only).
  void publishReplica(const session::Replica& r) override;

  // ---- a fleet (fleet_node.hpp) ----
  // Before run(): this server's id (else a random one).
  void setServerId(const std::string& id) { server_id_ = id; }
  const std::string& serverId() const { return server_id_; }
  // Before run(): routes requests through the fleet (placement, owners)
  // and hears the other servers' replicas, applied logs and heartbeats.
  void setFleet(FleetNode* fleet);
  session::SessionService& service() { return *service_; }
  // "fenced" (no lease), "draining", or null: a lone server, or a member in good standing.
  const char* fleetTrouble() const;

  // One received datagram, as LCM's handler gets it (also the entry of the
  // datagram fuzz target). Never throws: LCM's C code must not unwind.
  void handleDatagram(const std::string& channel, const void* data, int size) noexcept;
  void heartbeat();

  const std::string& url() const { return url_; }
  // The server's LCM instance: with memq:// a test publishes into it and
  // hears the answers in the same process.
  lcm::LCM& lcm() { return lcm_; }
  int workers() const { return service_->config().workers; }
  // Before run(): how much of what was published is kept for re-requests.
  void setResendLimits(const ResendLimits& limits);
  // Before run(): seconds between heartbeats (1 alone; a fleet beats faster
  // so that its clients tell a dead server within a second, docs/fleet.md).
  void setHeartbeatPeriod(double s) { heartbeat_period_ = s; }
  ResendRing::Stats resendStats();
  const session::ServiceConfig& config() const { return service_->config(); }

  // For GET /metrics and /health (metrics.hpp), from any thread: the
  // counters since start and the last heartbeat's figures (the service's
  // load is taken by the heartbeat, so it is not asked again here).
  struct Counters {
    std::int64_t states_published = 0, requests_handled = 0, errors = 0, heartbeats = 0;
    std::int64_t overrun_events = 0;      // real time overrun warnings (at most one per session per 5 s)
    std::int64_t standby_asks = 0, standby_repaired = 0;  // a standby's gap repair: frames asked for, entries resent
    std::int64_t standby_sessions = 0;                  // other servers' sessions kept as their standby
    bool beat = false;                    // a heartbeat was sent: the figures below are its
    int workers = 0, max_sessions = 0;
    double load = 0.0;                    // busy fraction of the worker pool over the last second
    int sessions_by_mode[4] = {0, 0, 0, 0};  // hosted sessions, by session::Mode - 1
  };
  Counters counters() const;

 private:
  // every client channel (requests, drives, controls, vectorised requests,
  // assets, resends): handleDatagram tells them apart by channel
  void onDatagram(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onFleet(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void handleFleet(const std::string& channel, const void* data, int size);
  bool mayPublish(const std::string& session_id) const;
  void handleResend(const std::string& channel, const void* data, int size);
  ResendRing::Scope resendScope(const groundsim::resend_t& msg);
  void handleAsset(const std::string& channel, const void* data, int size);
  void handleVecRequest(const std::string& channel, const void* data, int size);
  void handleRequest(const std::string& channel, const void* data, int size);
  void handleDrive(const std::string& channel, const void* data, int size);
  void handleControls(const std::string& channel, const void* data, int size);
  // Decodes a client's datagram into msg; one that does not decode is
  // reported as bad input on its channel (false).
  template <class Msg>
  bool decoded(Msg& msg, const char* type, const std::string& channel, const void* data, int size);
  // keep_session: also keep the bytes in the resend ring as that session's
  // frame keep_seq ("" and keep_seq >= 0: as event keep_seq); send false:
  // only keep them (a fenced owner's, for re-requests once its lease is back)
  template <class T>
  void publish(const std::string& channel, const T& msg, const std::string* keep_session = nullptr,
               std::int64_t keep_seq = -1, bool send = true);
  // Whether a session's messages go on the wire, are only kept (its owner
  // fenced), or neither (disowned: another server owns it).
  enum class Outlet { Send, Keep, Drop };
  Outlet outlet(const std::string& session_id) const;

  std::string url_;
  bool verbose_;
  lcm::LCM lcm_;
  std::mutex publish_mutex_;
  ResendRing ring_;  // under publish_mutex_
  std::string server_id_;
  FleetNode* fleet_ = nullptr;
  double heartbeat_period_ = 1.0;
  std::atomic<bool> drain_requested_{false};
  // a session was created or stopped: the next heartbeat goes out now, not
  // a period later (in a fleet the answerer lists others' sessions from
  // their heartbeats, so a list right after a create shows it)
  std::atomic<bool> beat_soon_{false};
  std::atomic<std::int64_t> replica_seq_{0}, ask_seq_{0}, applied_repaired_{0};
  std::atomic<std::int64_t> reply_seq_{0}, event_seq_{0}, status_seq_{0}, scenario_seq_{0}, vec_seq_{0},
      want_seq_{0};
  std::atomic<std::int64_t> frames_{0}, inputs_{0}, errors_{0}, overruns_{0};
  mutable std::mutex beat_mutex_;
  Counters beat_;  // under beat_mutex_: the last heartbeat's figures
  std::unique_ptr<session::SessionService> service_;  // after lcm_: it publishes through it
};

}  // namespace groundsim::net
