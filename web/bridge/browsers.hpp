// The browsers attached to the bridge, on the I/O thread: who each is (a
// serial number its creates are named by, the player name it gave), what
// it may still create, which session it is in and as what, and refusals
// sent to it (counted and, the first 20 of each browser, logged).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "bridge/browser_limits.hpp"
#include "bridge/browser_message.hpp"
#include "bridge/controls_throttle.hpp"
#include "bridge/peer.hpp"

namespace groundsim::web {

struct PeerState {
  std::uint64_t serial = 0;  // this browser's number (sessions it created name it; its creates' client id)
  std::shared_ptr<BrowserAllowance> allowance;
  int creating = 0;          // its creates awaiting the server's reply
  std::string player;        // the name the browser gave on create or join ("" : none); kept across sessions
  int logged = 0;            // refusals logged
  // in a session: which, as what, and its drive commands' throttle (a driver's)
  std::string session;
  Role role = Role::Spectate;
  int vehicle = -1;
  std::unique_ptr<ControlsThrottle> throttle;
  // ground grids: one computed at a time, the newest request waiting
  bool grid_busy = false;
  std::optional<GroundMsg> grid_next;

  // out of its session: what is the browser's, not its session's, stays
  void leaveSession();
};

class Browsers {
 public:
  Browsers(const BrowserLimits& limits, bool log) : limits_(limits), log_(log) {}

  PeerState& attach(Peer* p);
  void detach(Peer* p) { peers_.erase(p); }
  PeerState* find(Peer* p);
  // the browser numbered `serial`, if still attached (another may have taken its address)
  PeerState* find(Peer* p, std::uint64_t serial);
  bool attached(Peer* p) const { return peers_.count(p) > 0; }
  std::string nameOf(Peer* p) const;  // its player name ("" : none or gone)
  std::size_t size() const { return peers_.size(); }
  std::map<Peer*, PeerState>::iterator begin() { return peers_.begin(); }
  std::map<Peer*, PeerState>::iterator end() { return peers_.end(); }

  // {"op":"error"} naming the request, the field and the reason
  void refuse(Peer* p, const std::string& op, const std::string& field, const std::string& reason);
  std::int64_t refused() const { return refused_; }
  static void send(Peer* p, const std::string& text);

 private:
  const BrowserLimits& limits_;
  bool log_;
  std::map<Peer*, PeerState> peers_;
  std::uint64_t next_serial_ = 1;
  std::int64_t refused_ = 0;
};

}  // namespace groundsim::web
