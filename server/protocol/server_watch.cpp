#include "server_watch.hpp"

#include <algorithm>
#include <cstdio>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"

namespace groundsim::net {

ServerWatch::ServerWatch(lcm::LCM& lcm, double timeout_s)
    : lcm_(lcm), timeout_s_(timeout_s), start_(Clock::now()), since_(start_) {
  sub_ = lcm_.subscribe(kStatusChannel, &ServerWatch::onStatus, this);
}

ServerWatch::~ServerWatch() {
  if (sub_) lcm_.unsubscribe(sub_);
}

void ServerWatch::onStatus(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::server_status_t m;
  if (!decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.server_status_t").ok()) return;
  since_ = Clock::now();
  // forget servers silent for longer than the retention (a fleet's dead hosts)
  std::erase_if(last_, [&](const auto& kv) {
    return std::chrono::duration<double>(since_ - kv.second.at).count() > kFleetRetention;
  });
  const std::string id = m.server_id;
  auto it = last_.find(id);
  if (it == last_.end() && last_.size() >= kMaxServers) return;  // a flood of made-up server ids
  const long long beats = it == last_.end() ? 1 : it->second.beats + 1;
  double period = 0;  // unknown until a second beat
  if (it != last_.end()) {
    const double gap = std::chrono::duration<double>(since_ - it->second.at).count();
    period = it->second.period > 0 ? 0.75 * it->second.period + 0.25 * gap : gap;
  }
  last_[id] = Beat{std::move(m), since_, beats, period};
  ++count_;
}

double ServerWatch::silenceOf(const std::string& server_id, Clock::time_point now) const {
  auto it = last_.find(server_id);
  const Clock::time_point at = it == last_.end() ? start_ : it->second.at;
  return std::chrono::duration<double>(now - at).count();
}

double ServerWatch::timeoutOf(const std::string& server_id) const {
  auto it = last_.find(server_id);
  if (it == last_.end() || it->second.beats < 3 || it->second.period <= 0) return timeout_s_;
  return std::clamp(4 * it->second.period, std::min(1.0, timeout_s_), timeout_s_);
}

long long ServerWatch::rounds() const {
  long long n = -1;
  for (const auto& [id, b] : last_) n = n < 0 ? b.beats : std::min(n, b.beats);
  return std::max(0LL, n);
}

double ServerWatch::silence(Clock::time_point now) const {
  return std::chrono::duration<double>(now - since_).count();
}

bool ServerWatch::lost(Clock::time_point now) const { return silence(now) > timeout_s_; }

std::optional<groundsim::session_info_t> ServerWatch::session(const std::string& id) const {
  std::optional<groundsim::session_info_t> best;
  Clock::time_point best_at{};
  for (const auto& [server, b] : last_)
    for (const auto& s : b.status.sessions) {
      if (s.session_id != id) continue;
      // a higher epoch is the session's new owner; within one, the freshest beat
      if (!best || s.epoch > best->epoch || (s.epoch == best->epoch && b.at > best_at)) {
        best = s;
        best_at = b.at;
      }
    }
  return best;
}

std::vector<groundsim::session_info_t> ServerWatch::sessions() const {
  std::map<std::string, groundsim::session_info_t> by_id;
  for (const auto& [server, b] : last_)
    for (const auto& s : b.status.sessions) {
      auto it = by_id.find(s.session_id);
      if (it == by_id.end() || s.epoch > it->second.epoch) by_id[s.session_id] = s;
    }
  std::vector<groundsim::session_info_t> out;
  for (auto& [id, s] : by_id) out.push_back(std::move(s));
  return out;
}

std::string ServerWatch::lostMessage(const std::string& url, Clock::time_point now) const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f", silence(now));
  return std::string("no heartbeat from groundsim-server for ") + buf + " s on " + url +
         (count_ == 0 ? " (is the server running with the same --lcm-url?)" : " (the server stopped or was killed)");
}

}  // namespace groundsim::net
