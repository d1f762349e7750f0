#include "server_watch.hpp"

#include <cstdio>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"

namespace groundsim::net {

ServerWatch::ServerWatch(lcm::LCM& lcm, double timeout_s) : lcm_(lcm), timeout_s_(timeout_s), since_(Clock::now()) {
  sub_ = lcm_.subscribe(kStatusChannel, &ServerWatch::onStatus, this);
}

ServerWatch::~ServerWatch() {
  if (sub_) lcm_.unsubscribe(sub_);
}

void ServerWatch::onStatus(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::server_status_t m;
  if (!decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.server_status_t").ok()) return;
  last_ = std::move(m);
  since_ = Clock::now();
  ++count_;
}

double ServerWatch::silence(Clock::time_point now) const {
  return std::chrono::duration<double>(now - since_).count();
}

bool ServerWatch::lost(Clock::time_point now) const { return silence(now) > timeout_s_; }

std::optional<groundsim::session_info_t> ServerWatch::session(const std::string& id) const {
  if (!last_) return std::nullopt;
  for (const auto& s : last_->sessions)
    if (s.session_id == id) return s;
  return std::nullopt;
}

std::vector<groundsim::session_info_t> ServerWatch::sessions() const {
  return last_ ? last_->sessions : std::vector<groundsim::session_info_t>{};
}

std::string ServerWatch::lostMessage(const std::string& url, Clock::time_point now) const {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.1f", silence(now));
  return std::string("no heartbeat from groundsim-server for ") + buf + " s on " + url +
         (count_ == 0 ? " (is the server running with the same --lcm-url?)" : " (the server stopped or was killed)");
}

}  // namespace groundsim::net
