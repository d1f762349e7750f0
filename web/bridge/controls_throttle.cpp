#include "bridge/controls_throttle.hpp"

#include "bridge/hub.hpp"
#include "bridge/session_table.hpp"
#include "lcm/latency_trace.hpp"

namespace groundsim::web {

using Clock = std::chrono::steady_clock;

ControlsThrottle::ControlsThrottle(boost::asio::io_context& io, std::string session, Send send)
    : session_(std::move(session)), send_(std::move(send)), timer_(io) {}

ControlsThrottle::~ControlsThrottle() {
  *alive_ = false;
  timer_.cancel();
}

void ControlsThrottle::submit(const ControlsMsg& m) {
  const auto now = Clock::now();
  const auto due = last_ + kPeriod;
  if (now >= due) return sendNow(m, now);
  if (held_ && net::LatencyTrace::on())
    net::LatencyTrace::line("ctl %s %.0f -1 %lld -1", session_.c_str(), held_->seq,
                            static_cast<long long>(net::LatencyTrace::us(held_rx_)));
  const bool waiting = held_.has_value();
  held_ = m;
  held_rx_ = now;
  if (waiting) return;
  timer_.expires_at(due);
  timer_.async_wait([this, alive = std::weak_ptr<bool>(alive_)](const boost::system::error_code& ec) {
    const auto a = alive.lock();
    if (!ec && a && *a) sendHeld();
  });
}

void ControlsThrottle::sendHeld() {
  if (!held_) return;
  const ControlsMsg m = *held_;
  held_.reset();
  sendNow(m, held_rx_);
}

void ControlsThrottle::sendNow(const ControlsMsg& m, Clock::time_point rx) {
  last_ = Clock::now();
  const std::int64_t seq = seq_++;
  send_(m, seq, rx);
  if (net::LatencyTrace::on())
    net::LatencyTrace::line("ctl %s %.0f %lld %lld %lld", session_.c_str(), m.seq, static_cast<long long>(seq),
                            static_cast<long long>(net::LatencyTrace::us(rx)),
                            static_cast<long long>(net::LatencyTrace::nowUs()));
}

void publishControls(const Bus& bus, const ControlScale& scale, const SessionEntry& s, const std::string& session,
                     int vehicle, const Controls& c, std::int64_t seq) {
  const auto utime =
      std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
  const bool road_car = static_cast<size_t>(vehicle) < s.view->road_car.size() && s.view->road_car[vehicle];
  if (road_car) {
    groundsim::controls_t m = toCarControls(c, vehicle);
    m.utime = utime;
    m.seq = seq;
    m.client_id = bus.client_id;
    m.session_id = session;
    m.token = s.token;
    if (bus.controls) bus.controls(m);
    return;
  }
  groundsim::drive_t d = toDrive(c, vehicle, s.view->wheels[vehicle], scale);
  d.utime = utime;
  d.seq = seq;
  d.client_id = bus.client_id;
  d.session_id = session;
  d.token = s.token;
  bus.drive(d);
}

}  // namespace groundsim::web
