// The bridge's logic, on the I/O thread, wired from small parts with one
// owner each (docs/architecture.md, The bridge): Browsers (who is attached),
// SessionTable (the sessions they see), Requests (to the server, and the
// replies), Creates (the sessions this bridge creates and ends), Seats
// (joining and leaving), ControlsThrottle (a driver's commands), Lobby and
// Previews. The Hub routes browser messages and bus messages to them. LCM
// callbacks (on the LCM thread) only decode, re-encode and post here; scene
// views, ground grids and previews are computed on the worker thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bridge/browser_limits.hpp"
#include "bridge/browsers.hpp"
#include "bridge/browser_message.hpp"
#include "bridge/controls.hpp"
#include "bridge/creates.hpp"
#include "bridge/lcm_link.hpp"
#include "bridge/lobby.hpp"
#include "bridge/peer.hpp"
#include "bridge/previews.hpp"
#include "bridge/requests.hpp"
#include "bridge/seats.hpp"
#include "bridge/session_table.hpp"
#include "bridge/shipped_scenarios.hpp"
#include "bridge/worker.hpp"

namespace groundsim::web {

struct HubConfig {
  std::string configs_dir;        // the shipped scenarios a browser may create sessions from (subfolders too)
  int max_vehicles = 32;          // the server's --max-vehicles: no create asks for more cars
  ControlScale scale;
  int grid_n = 81;                // ground grid nodes per side
  double grid_step = 0.5;         // m between nodes
  double vehicle_margin = 1.0;    // m between the copies of a car (create with "vehicles")
  double reply_timeout_s = 3.0;   // s  a request without reply is answered as failed
  double orphan_stop_s = 8.0;     // s  a session this bridge created, watched by nobody, is stopped (--orphan-stop)
  BrowserLimits limits;           // what one browser may create (browser_limits.hpp)
  bool log = true;                // refusals and connections on stderr
};

// What the hub publishes (LcmLink in the bridge, a recorder in tests).
struct Bus {
  std::string client_id;
  std::function<void(const groundsim::request_t&)> request;
  std::function<void(const groundsim::drive_t&)> drive;
  std::function<void(const groundsim::controls_t&)> controls;  // road cars
  // the parts of a create's files the server asked for (any thread: the hub's worker calls it)
  std::function<void(const std::vector<scenario::Asset>&, const std::vector<groundsim::asset_want_t>&)> assets;
};

class Hub {
 public:
  Hub(boost::asio::io_context& io, HubConfig cfg, Bus bus);
  ~Hub();

  // LCM thread: callbacks that only re-encode and post to the I/O thread.
  LcmHandlers lcmHandlers();

  // I/O thread.
  void attach(Peer* p);
  void detach(Peer* p);
  void onText(Peer* p, const std::string& text);
  void onBinary(Peer* p);
  // Stops the sessions this bridge created (at shutdown).
  void stopOwnedSessions() { creates_.stopAll(); }
  const std::vector<std::string>& configs() const { return configs_; }
  const BrowserLimits& limits() const { return cfg_.limits; }
  const std::map<std::string, ShippedScenario>& scenarios() const { return scenarios_; }

  // Any thread: whether a browser watches the session, and a message for
  // the newest-only `slot` of every browser watching it (posted to the I/O
  // thread). Feeds beside the hub's own channels use these (contact_feed.hpp).
  bool watched(const std::string& id) { return sessions_.watched(id); }
  void postToWatchers(const std::string& id, Slot slot, std::shared_ptr<const std::string> json);

  // Counters, for logs, tests and GET /metrics (web_server.cpp).
  std::int64_t refused() const { return browsers_.refused(); }
  // I/O thread: browsers attached, sessions at least one of them watches.
  std::size_t browsers() const { return browsers_.size(); }
  std::size_t sessionsWatched() const { return sessions_.watchedCount(); }
  // Any thread: messages from the bus dropped as undecodable (contact feed's too).
  std::uint64_t undecodable() const { return undecodable_.load(); }

 private:
  HubContext context();   // what the parts share
  void offerScenarios();  // the shipped scenarios and the welcome every browser is sent
  void handle(Peer* p, PeerState& ps, const BrowserMessage& m);
  void controls(Peer* p, PeerState& ps, const ControlsMsg& m);
  void sessionOp(Peer* p, PeerState& ps, const SessionOpMsg& m);
  void ground(Peer* p, PeerState& ps, const GroundMsg& m);
  void pong(Peer* p, const PingMsg& m);
  void onState(const groundsim::state_t& s);  // LCM thread
  void toWatchers(const std::string& id, Slot slot, std::shared_ptr<const std::string> json);
  void onEvent(const groundsim::event_t& e, std::shared_ptr<const std::string> json);
  void tick();  // 1 Hz: lobby, orphaned sessions

  boost::asio::io_context& io_;
  HubConfig cfg_;
  Bus bus_;
  std::vector<std::string> configs_;                  // ids of scenarios_, in the lobby's order
  std::map<std::string, ShippedScenario> scenarios_;  // by id
  std::shared_ptr<const std::string> welcome_;        // the same for every browser
  std::atomic<std::uint64_t> undecodable_{0};  // LCM thread
  boost::asio::steady_timer ticker_;

  Worker worker_;  // its thread stops before the parts below go (their jobs name them)
  Browsers browsers_;
  SessionTable sessions_;
  Requests requests_;
  Lobby lobby_;
  Previews previews_;
  Creates creates_;
  Seats seats_;
};

}  // namespace groundsim::web
