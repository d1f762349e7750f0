// The sessions this bridge creates for its browsers, from the shipped
// scenarios (docs/front-end.md, Lobby): a create checked against the
// scenario and the browser's limits, sent with the files the scenario names
// (rounds of the parts the server asks for, on the worker), and the reply
// that makes the session this bridge's (its token, never sent to a
// browser). Ends them too: a browser's unwatched sessions when it is at its
// limit, sessions nobody watched for --orphan-stop, all at shutdown.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <groundsim/asset_want_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>

#include "bridge/hub_context.hpp"
#include "bridge/shipped_scenarios.hpp"
#include "scenario/assets.hpp"
#include "scenario/file_access.hpp"

namespace groundsim::web {

class Creates {
 public:
  // joins the creating browser to its new session
  using Join = std::function<void(Peer*, const JoinMsg&)>;

  Creates(const HubContext& c, const std::map<std::string, ShippedScenario>& scenarios, Join join);

  void create(Peer* p, PeerState& ps, const CreateMsg& m);
  // LCM: the parts of a create's files the server asked for (one of ours)
  void noteWant(const groundsim::asset_want_t& w);
  // The files a session's scenario names, from those this bridge sent (by hash).
  scenario::FileAccess knownAssets(const std::string& scenario_json) const;

  void stop(const std::string& id, SessionEntry& s);  // a session this bridge created (its token)
  void stopOrphans(std::chrono::steady_clock::time_point now);  // nobody watched them for --orphan-stop
  void stopAll();  // at shutdown

 private:
  // a listed scenario, with as many cars (and bots) as it hosts
  bool fits(Peer* p, const CreateMsg& c, const ShippedScenario& s);
  // a browser's create against its limits (browser_limits.hpp); at its
  // session limit, its own sessions nobody watches end first
  bool allowed(Peer* p, PeerState& ps, const CreateMsg& c, const ShippedScenario& s);
  // the scenario document to create: the shipped file with the bots and cars asked for
  std::optional<std::string> document(Peer* p, const CreateMsg& m);
  // One round of a create: a refusal for missing files sends the parts the
  // server asked for (on the worker) and creates again, up to net::kAssetRounds.
  void round(Peer* p, std::uint64_t serial, groundsim::request_t r,
             std::shared_ptr<const std::vector<scenario::Asset>> assets, bool drive, int round);
  void sendAssetsAndRetry(Peer* p, std::uint64_t serial, groundsim::request_t r,
                          std::shared_ptr<const std::vector<scenario::Asset>> assets, bool drive, int round,
                          std::int64_t answered);
  // The create's reply: the session is this bridge's (and its creator's)
  // whether or not the creating browser is still there.
  void created(Peer* p, std::uint64_t serial, const groundsim::reply_t& rep, const std::string& doc, bool drive);

  HubContext c_;
  const std::map<std::string, ShippedScenario>& scenarios_;
  Join join_;
  std::map<std::int64_t, std::vector<groundsim::asset_want_t>> wants_;     // by request id (ours only)
  std::map<std::string, std::shared_ptr<const std::string>> asset_bytes_;  // files sent, by sha256
};

}  // namespace groundsim::web
