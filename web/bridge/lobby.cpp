#include "bridge/lobby.hpp"

#include <algorithm>

#include "bridge/browser_message.hpp"
#include "protocol/names.hpp"

namespace groundsim::web {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

Lobby::Lobby(boost::asio::io_context& io, Browsers& browsers, SessionTable& sessions)
    : browsers_(browsers), sessions_(sessions), timer_(io) {}

Lobby::~Lobby() { timer_.cancel(); }

void Lobby::onStatus(const groundsim::server_status_t& s) {
  status_ = s;
  status_time_ = Clock::now();
  have_status_ = true;
  publish();
}

void Lobby::publish() {
  if (due_) return;
  const auto now = Clock::now();
  if (now - sent_ >= kPeriod) return publishNow();
  due_ = true;
  timer_.expires_at(sent_ + kPeriod);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    due_ = false;
    publishNow();
  });
}

bool Lobby::fresh(Clock::time_point now) const { return have_status_ && now - status_time_ < std::chrono::seconds(3); }

void Lobby::publishNow() {
  const auto now = Clock::now();
  sent_ = now;
  std::set<std::string> listed;
  json sessions = fresh(now) ? serverSessions(listed) : json::array();
  for (json& j : busSessions(listed, now)) sessions.push_back(std::move(j));
  json lobby = {{"op", "lobby"}, {"sessions", sessions}, {"server", nullptr}};
  if (fresh(now))
    lobby["server"] = {{"id", status_.server_id}, {"workers", status_.workers}, {"load", status_.load},
                       {"sessions", status_.nsessions}, {"errors", status_.errors}};
  auto text = std::make_shared<const std::string>(lobby.dump());
  for (auto& [p, ps] : browsers_) p->sendLatest(Slot::Lobby, text);
}

json Lobby::seats(const std::string& id) {
  int drivers = 0, free = 0, watchers = 0;
  bool owned = false, unsized = true;
  // who is in: a name per vehicle (null: free, "": a driver who gave none)
  // and the spectators' names
  json players = json::array(), spectators = json::array();
  if (const SessionEntry* s = sessions_.find(id)) {
    unsized = s->drivers.empty();
    owned = s->owned();
    watchers = static_cast<int>(s->watchers.size());
    for (Peer* d : s->drivers) {
      d ? ++drivers : ++free;
      players.push_back(d ? json(browsers_.nameOf(d)) : json(nullptr));
    }
    for (Peer* w : s->watchers)
      if (std::find(s->drivers.begin(), s->drivers.end(), w) == s->drivers.end())
        spectators.push_back(browsers_.nameOf(w));
  }
  json j;
  j["players"] = std::move(players);
  j["spectators"] = std::move(spectators);
  j["drivable"] = owned && (free > 0 || unsized);
  j["free"] = free;
  j["drivers"] = drivers;
  j["watchers"] = watchers;
  return j;
}

json Lobby::serverSessions(std::set<std::string>& listed) {
  json out = json::array();
  for (const auto& si : status_.sessions) {
    json j = seats(si.session_id);
    j["id"] = si.session_id;
    j["name"] = si.name;
    j["mode"] = net::modeName(si.mode);
    j["status"] = si.status;
    j["reason"] = si.status_reason;
    j["t"] = si.utime * 1e-6;
    j["rate"] = si.rate;
    j["publish_rate"] = si.publish_rate;
    j["vehicles"] = si.vehicle_names;
    j["wheel_counts"] = std::vector<int>(si.wheel_counts.begin(), si.wheel_counts.end());
    j["dt"] = si.dt;
    j["num_envs"] = si.num_envs;  // > 0: a vectorised session (nothing to draw: it publishes no states)
    j["source"] = "server";
    listed.insert(si.session_id);
    out.push_back(std::move(j));
  }
  return out;
}

// states on the bus that no heartbeat lists: a replay, or another server's
json Lobby::busSessions(const std::set<std::string>& listed, Clock::time_point now) {
  json out = json::array();
  for (const BusSession& b : sessions_.onBus(now, std::chrono::seconds(5))) {
    if (listed.count(b.id) || !validSessionId(b.id)) continue;
    json j = seats(b.id);
    j["id"] = b.id;
    j["name"] = "";
    j["mode"] = "unknown";
    j["status"] = 1;
    j["reason"] = "";
    j["t"] = b.t;
    j["vehicles"] = json::array();
    j["source"] = "bus";
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace groundsim::web
