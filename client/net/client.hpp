// A client's connection to groundsim-server: requests matched to their
// replies by request id (with a timeout and a clear error when no server
// answers), drive commands, the events addressed to this client, and the
// server's heartbeat: every wait ends with NetError once no heartbeat has
// arrived for net::kHeartbeatTimeout, so no command outlives its server.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <chrono>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/controls_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>

#include "protocol/assets_client.hpp"
#include "protocol/server_watch.hpp"

namespace groundsim::cli {

struct NetError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class NetClient {
 public:
  // deep_receive: an 8 MiB socket buffer (for subscribers that must not lose
  // messages). Throws NetError when the URL cannot be opened.
  explicit NetClient(const std::string& url, bool deep_receive = false);

  lcm::LCM& lcm() { return lcm_; }
  const std::string& url() const { return url_; }
  const std::string& clientId() const { return client_id_; }

  // Fills utime, seq, request_id and client_id, publishes, and waits for the
  // reply. Throws NetError on timeout or when the heartbeat stops (a step
  // of millions of steps waits as long as the server lives, up to
  // timeout_s). A refused request returns ok = false.
  groundsim::reply_t call(groundsim::request_t req, double timeout_s);
  // An OP_CREATE whose scenario names `assets` (its "assets" manifest):
  // when the server lacks some, sends the parts it asks for and creates
  // again, up to net::kAssetRounds times. A file the server refuses (its
  // hash does not match, it is too large) ends it with that reason.
  groundsim::reply_t create(const groundsim::request_t& req, const std::vector<scenario::Asset>& assets,
                            double timeout_s);
  // Handles messages for up to ms milliseconds; throws NetError when the
  // server's heartbeat has stopped.
  void pump(int ms);
  const net::ServerWatch& server() const { return watch_; }
  void send(groundsim::drive_t cmd);
  void send(groundsim::controls_t cmd);  // road cars, on GROUNDSIM_CONTROLS

  // Error events addressed to this client since the last call.
  std::vector<groundsim::event_t> takeEvents();

 private:
  static constexpr std::chrono::milliseconds kAskAgain{1000};  // call(): idempotent requests asked again
  void onReply(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onEvent(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  void onAssetWant(const lcm::ReceiveBuffer* rbuf, const std::string& channel);

  std::string url_;
  lcm::LCM lcm_;
  std::string client_id_;
  std::int64_t seq_ = 0;
  std::int64_t waiting_for_ = -1;
  std::optional<groundsim::reply_t> reply_;
  std::vector<groundsim::event_t> events_;
  net::AssetWants wants_;  // client_id_'s
  net::ServerWatch watch_;  // after lcm_
};

std::int64_t wallMicros();

}  // namespace groundsim::cli
