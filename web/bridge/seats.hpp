// Browsers joining and leaving sessions: a watcher's seat, or a driver's
// car (only in sessions this bridge created: it holds their tokens). A join
// waits for the session's scene view (built on the worker from the scenario
// document, asked of the server when the bus has not shown it), then gets
// the layout, the scenario (a driver's page predicts its car with it) and a
// race's catch-up. Leaving releases a driver's car.
#pragma once

#include <functional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <groundsim/scenario_t.hpp>

#include "bridge/creates.hpp"
#include "bridge/hub_context.hpp"
#include "bridge/lobby.hpp"

namespace groundsim::web {

class Seats {
 public:
  Seats(const HubContext& c, Lobby& lobby, const Creates& creates);

  void join(Peer* p, const JoinMsg& m);
  void leave(Peer* p);
  // LCM: a session's scenario document (joins waiting for it go on)
  void onScenario(const groundsim::scenario_t& m);

 private:
  // joins waiting for the view go on once it is there (or cannot be)
  void ensureView(const std::string& id);
  void buildView(const std::string& id, SessionEntry& s, const std::string& doc);
  void fetchScenario(const std::string& id, SessionEntry& s);
  void finishJoin(Peer* p, const JoinMsg& m);
  // the car a driver takes (-1: refused, said to the browser)
  int seatDriver(Peer* p, const JoinMsg& m, SessionEntry& s);
  std::string joinedMessage(const PeerState& ps, const std::string& session, const SessionEntry& s) const;

  HubContext c_;
  Lobby& lobby_;
  const Creates& creates_;
};

}  // namespace groundsim::web
