// The bridge's logic, on the I/O thread: which browser watches or drives
// which session, the tokens of the sessions this bridge created, the lobby,
// and the translation of browser messages to requests and drive commands.
// LCM callbacks (on the LCM thread) only decode, re-encode and post here;
// scene views and ground grids are computed on the worker thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bridge/browser_limits.hpp"
#include "bridge/browser_message.hpp"
#include "bridge/controls.hpp"
#include "bridge/lcm_link.hpp"
#include "bridge/peer.hpp"
#include "bridge/race_relay.hpp"
#include "bridge/scene_view.hpp"
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
  void stopOwnedSessions();
  const std::vector<std::string>& configs() const { return configs_; }
  const BrowserLimits& limits() const { return cfg_.limits; }
  const std::map<std::string, ShippedScenario>& scenarios() const { return scenarios_; }

  // Any thread: whether a browser watches the session, and a message for
  // the newest-only `slot` of every browser watching it (posted to the I/O
  // thread). Feeds beside the hub's own channels use these (contact_feed.hpp).
  bool watched(const std::string& id);
  void postToWatchers(const std::string& id, Slot slot, std::shared_ptr<const std::string> json);

  // Counters, for logs, tests and GET /metrics (web_server.cpp).
  std::int64_t refused() const { return refused_; }
  // I/O thread: browsers attached, sessions at least one of them watches.
  std::size_t browsers() const { return peers_.size(); }
  std::size_t sessionsWatched() const;
  // Any thread: messages from the bus dropped as undecodable (contact feed's too).
  std::uint64_t undecodable() const { return undecodable_.load(); }

 private:
  struct PeerState {
    std::uint64_t serial = 0;  // this browser's number (sessions it created name it; its creates' client id)
    std::shared_ptr<BrowserAllowance> allowance;
    int creating = 0;          // its creates awaiting the server's reply
    std::string session;
    Role role = Role::Spectate;
    int vehicle = -1;
    std::int64_t drive_seq = 0;
    std::chrono::steady_clock::time_point last_drive{};
    // controls that came within kControlsPeriod of the last sent: the
    // newest, sent by hold_timer when the period is over
    std::optional<ControlsMsg> held;
    std::chrono::steady_clock::time_point held_rx{};
    std::shared_ptr<boost::asio::steady_timer> hold_timer;
    std::string player;  // the name the browser gave on create or join ("" : none); kept across sessions
    bool grid_busy = false;
    std::optional<GroundMsg> grid_next;
    int logged = 0;
  };
  struct SessionEntry {
    std::string token;                     // "" unless this bridge created it
    std::uint64_t creator = 0;             // the browser that created it (PeerState::serial; 0: none)
    std::shared_ptr<SceneView> view;
    std::shared_ptr<const std::string> joined_layout;  // view->layout dumped once
    bool view_failed = false;
    std::string view_error;
    bool building = false, fetching = false;
    std::vector<Peer*> drivers;            // per vehicle; nullptr: free
    std::set<Peer*> watchers;
    std::vector<std::pair<Peer*, JoinMsg>> pending;
    std::chrono::steady_clock::time_point unwatched_since{};
    RaceRelay race;                        // its race's last layout and standings
  };
  struct BusSeen {
    double t = 0;
    int nvehicles = 0;
    std::chrono::steady_clock::time_point last{};
  };

  void handle(Peer* p, PeerState& ps, const BrowserMessage& m);
  void create(Peer* p, PeerState& ps, const CreateMsg& m, const ShippedScenario& sc);
  // One round of a create: a refusal for missing files sends the parts the
  // server asked for (on the worker) and creates again, up to net::kAssetRounds.
  void createRound(Peer* p, std::uint64_t serial, groundsim::request_t r,
                   std::shared_ptr<const std::vector<scenario::Asset>> assets, bool drive, int round);
  // The create's reply: the session is this bridge's (and its creator's)
  // whether or not the creating browser is still there.
  void created(Peer* p, std::uint64_t serial, const groundsim::reply_t& rep, const std::string& doc, bool drive);
  bool ours(const std::string& client_id) const;  // the bridge's id, or one of its browsers' (id-bN)
  // The files a session's scenario names, from those this bridge sent (by hash).
  scenario::FileAccess knownAssets(const std::string& scenario_json) const;
  void join(Peer* p, const JoinMsg& m);
  void finishJoin(Peer* p, const JoinMsg& m);
  void leave(Peer* p);
  void controls(Peer* p, PeerState& ps, const ControlsMsg& m);
  void sendHeld(Peer* p, const std::weak_ptr<boost::asio::steady_timer>& timer);
  void driveNow(PeerState& ps, const ControlsMsg& m, std::chrono::steady_clock::time_point rx);
  void ground(Peer* p, PeerState& ps, const GroundMsg& m);
  // A shipped scenario's picture data (scenarioPreview), computed once on
  // the worker and kept: at most one per shipped file for the bridge's life.
  void preview(Peer* p, const PreviewMsg& m);
  void sessionOp(Peer* p, PeerState& ps, const SessionOpMsg& m);
  void refuse(Peer* p, const std::string& op, const std::string& field, const std::string& reason);
  // A browser's create against its limits (browser_limits.hpp); at its
  // session limit, its own sessions nobody watches end first.
  bool allowCreate(Peer* p, PeerState& ps, const CreateMsg& c, const ShippedScenario& s);
  int ownedBy(std::uint64_t serial) const;
  void stopSession(const std::string& id, SessionEntry& s);  // a session this bridge created (its token)
  groundsim::request_t stopRequest(const std::string& id, const std::string& token) const;
  void sendJson(Peer* p, const std::string& text);

  void request(groundsim::request_t r, std::function<void(const groundsim::reply_t*)> done);
  void ensureView(const std::string& id);
  void onReply(const groundsim::reply_t& r);
  void onScenario(const groundsim::scenario_t& s);
  void onEvent(const groundsim::event_t& e, std::shared_ptr<const std::string> json);
  void onState(const std::string& id, std::shared_ptr<const std::string> json);
  void onCarState(const std::string& id, std::shared_ptr<const std::string> json);
  // The player's controls to the server: controls_t for a road car, else drive_t.
  void sendControls(const SessionEntry& s, const std::string& session, int vehicle, const Controls& c,
                    std::int64_t seq);
  void onStatus(const groundsim::server_status_t& s);
  void tick();  // 1 Hz: lobby, orphaned sessions
  void publishLobby();     // soon (coalesced: at most one every 50 ms)
  void publishLobbyNow();
  void updateWatched(const std::string& id);

  boost::asio::io_context& io_;
  HubConfig cfg_;
  Bus bus_;
  std::vector<std::string> configs_;                  // ids of scenarios_, in the lobby's order
  std::map<std::string, ShippedScenario> scenarios_;  // by id
  std::shared_ptr<const std::string> welcome_;        // the same for every browser
  std::map<Peer*, PeerState> peers_;
  std::map<std::string, SessionEntry> sessions_;
  std::map<std::string, std::string> scenario_texts_;  // session -> scenario document seen on the bus
  std::map<std::string, std::shared_ptr<const std::string>> previews_;  // config -> its preview message
  std::map<std::string, std::vector<Peer*>> preview_waiting_;          // config -> browsers waiting for it
  // one preview at a time on the worker, behind whatever it holds: a
  // session's scene view or ground grid waits for one preview at most
  std::deque<std::string> preview_queue_;
  bool preview_busy_ = false;
  void nextPreview();
  std::int64_t next_request_ = 1;
  std::uint64_t next_browser_ = 1;
  struct Pending {
    std::function<void(const groundsim::reply_t*)> done;
    std::shared_ptr<boost::asio::steady_timer> timer;
  };
  std::map<std::int64_t, Pending> pending_;
  std::map<std::int64_t, std::vector<groundsim::asset_want_t>> wants_;  // by request id (ours only)
  std::map<std::string, std::shared_ptr<const std::string>> asset_bytes_;  // files sent, by sha256
  groundsim::server_status_t status_{};
  std::chrono::steady_clock::time_point status_time_{};
  bool have_status_ = false;
  std::int64_t refused_ = 0;
  std::atomic<std::uint64_t> undecodable_{0};  // LCM thread
  boost::asio::steady_timer ticker_;
  boost::asio::steady_timer lobby_timer_;
  bool lobby_due_ = false;
  std::chrono::steady_clock::time_point lobby_sent_{};

  // shared with the LCM thread
  std::mutex shared_mu_;
  std::unordered_map<std::string, int> watched_;   // session -> browsers watching
  std::unordered_map<std::string, BusSeen> seen_;  // sessions whose states are on the bus

  Worker worker_;  // last: its thread stops before the rest goes
};

}  // namespace groundsim::web
