// The sessions the bridge's browsers see (docs/architecture.md, The bridge):
// one entry per session a browser watches, drives, or this bridge created,
// created only by open() and removed only by prune(). Beside the entries, on
// the I/O thread: the scenario documents seen on the bus. Shared with the
// LCM thread (behind a mutex): how many browsers watch each session and the
// sessions whose states are on the bus.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bridge/browser_message.hpp"
#include "bridge/peer.hpp"
#include "bridge/race_relay.hpp"
#include "bridge/scene_view.hpp"

namespace groundsim::web {

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

  bool owned() const { return !token.empty(); }
  // nothing holds it: not ours, nobody watching or joining, no work under way
  bool idle() const { return !owned() && watchers.empty() && pending.empty() && !building && !fetching; }
};

// A session whose states are on the bus (a replay's, another server's ...).
struct BusSession {
  std::string id;
  double t = 0;  // its newest state's time
};

class SessionTable {
 public:
  using Map = std::map<std::string, SessionEntry>;

  // I/O thread.
  SessionEntry& open(const std::string& id);  // the entry, made if there is none
  SessionEntry* find(const std::string& id);
  const SessionEntry* find(const std::string& id) const;
  // Forgets the entries nothing holds (SessionEntry::idle): a hostile
  // browser cannot grow the table.
  void prune();
  Map::iterator begin() { return entries_.begin(); }
  Map::iterator end() { return entries_.end(); }
  std::size_t watchedCount() const;            // sessions with at least one watcher
  int ownedBy(std::uint64_t creator) const;    // sessions this bridge created for that browser
  // the scenario document a session runs, as seen on the bus or sent by a
  // create (kept: a replay's is published once, when it starts). Documents
  // of sessions without an entry are kept up to kMaxDetached of them and
  // kMaxDetachedBytes in all, the oldest forgotten first (a session asked
  // for again is fetched from the server): the bus cannot grow it unbounded.
  static constexpr std::size_t kMaxDetached = 256;
  static constexpr std::size_t kMaxDetachedBytes = std::size_t{64} << 20;
  void setScenario(const std::string& id, std::string doc);
  const std::string* scenario(const std::string& id) const;
  // publishes the session's watcher count to the LCM thread
  void updateWatched(const std::string& id);

  // Any thread.
  bool watched(const std::string& id);
  // LCM thread: a state of the session was on the bus; whether anyone watches it.
  bool noteBusState(const std::string& id, double t, std::chrono::steady_clock::time_point now);
  // The sessions with a state on the bus within the last `within`, oldest forgotten.
  std::vector<BusSession> onBus(std::chrono::steady_clock::time_point now, std::chrono::seconds within);

 private:
  Map entries_;
  void forgetOldScenarios();
  std::map<std::string, std::string> scenarios_;  // session -> scenario document
  std::deque<std::string> scenario_order_;         // sessions of scenarios_, oldest first

  struct Seen {
    double t = 0;
    std::chrono::steady_clock::time_point last{};
  };
  std::mutex shared_mu_;
  std::unordered_map<std::string, int> watched_;  // session -> browsers watching
  std::unordered_map<std::string, Seen> seen_;    // sessions whose states are on the bus
};

}  // namespace groundsim::web
