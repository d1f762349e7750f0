// The lobby every browser sees: the server's sessions (from its heartbeat),
// sessions on the bus that no heartbeat lists (a replay, another server's),
// and who is in each. Published at most once every kPeriod: joins, leaves
// and connections (a page can cause hundreds a second) publish it at once
// when the last is older than that (so it reaches a page before the answer
// that caused it), else mark it due for one timer that builds it once for
// every browser.
#pragma once

#include <chrono>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <groundsim/server_status_t.hpp>
#include <nlohmann/json.hpp>

#include "bridge/browsers.hpp"
#include "bridge/session_table.hpp"

namespace groundsim::web {

class Lobby {
 public:
  static constexpr auto kPeriod = std::chrono::milliseconds(50);

  Lobby(boost::asio::io_context& io, Browsers& browsers, SessionTable& sessions);
  ~Lobby();

  void publish();  // soon (coalesced)
  void onStatus(const groundsim::server_status_t& s);

 private:
  void publishNow();
  nlohmann::json seats(const std::string& id);  // who is in a session, and whether a browser may drive it
  nlohmann::json serverSessions(std::set<std::string>& listed);
  nlohmann::json busSessions(const std::set<std::string>& listed, std::chrono::steady_clock::time_point now);
  bool fresh(std::chrono::steady_clock::time_point now) const;

  Browsers& browsers_;
  SessionTable& sessions_;
  groundsim::server_status_t status_{};
  std::chrono::steady_clock::time_point status_time_{};
  bool have_status_ = false;
  boost::asio::steady_timer timer_;
  bool due_ = false;
  std::chrono::steady_clock::time_point sent_{};
};

}  // namespace groundsim::web
