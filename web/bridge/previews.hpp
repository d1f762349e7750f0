// A shipped scenario's picture data for the lobby's cards (scenarioPreview,
// shipped_scenarios.hpp), computed once on the worker and kept: at most one
// per shipped file for the bridge's life. One preview at a time on the
// worker, behind whatever it holds, so that a session's scene view or ground
// grid waits for one preview at most; browsers asking for one under way wait
// for it.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>

#include "bridge/browsers.hpp"
#include "bridge/peer.hpp"
#include "bridge/worker.hpp"

namespace groundsim::web {

class Previews {
 public:
  Previews(boost::asio::io_context& io, Worker& worker, const Browsers& browsers, std::string configs_dir);

  // The preview of shipped scenario `config` (a listed id) to `p`, now or when computed.
  void ask(Peer* p, const std::string& config);

 private:
  void next();

  boost::asio::io_context& io_;
  Worker& worker_;
  const Browsers& browsers_;
  std::string dir_;
  std::map<std::string, std::shared_ptr<const std::string>> done_;  // config -> its preview message
  std::map<std::string, std::vector<Peer*>> waiting_;              // config -> browsers waiting for it
  std::deque<std::string> queue_;
  bool busy_ = false;
};

}  // namespace groundsim::web
