// A browser's drive commands to the server, at most one per period: one
// that comes sooner is held, the newest replacing an older, and sent when
// the period is over. Dropped instead, a key press or release that came
// right after the page's periodic re-send (or in a burst after a stall)
// would wait for the next re-send, 50 ms on. One per browser and session:
// destroying it (the browser left) forgets what it held.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bridge/browser_message.hpp"
#include "bridge/controls.hpp"

namespace groundsim::web {

struct Bus;
struct SessionEntry;

class ControlsThrottle {
 public:
  static constexpr auto kPeriod = std::chrono::milliseconds(4);
  // sends one command with its sequence number and the time it was received
  using Send = std::function<void(const ControlsMsg&, std::int64_t seq, std::chrono::steady_clock::time_point rx)>;

  ControlsThrottle(boost::asio::io_context& io, std::string session, Send send);
  ~ControlsThrottle();
  ControlsThrottle(const ControlsThrottle&) = delete;
  ControlsThrottle& operator=(const ControlsThrottle&) = delete;

  void submit(const ControlsMsg& m);

 private:
  void sendNow(const ControlsMsg& m, std::chrono::steady_clock::time_point rx);
  void sendHeld();

  std::string session_;  // for the latency trace
  Send send_;
  std::int64_t seq_ = 0;
  std::chrono::steady_clock::time_point last_{};
  std::optional<ControlsMsg> held_;
  std::chrono::steady_clock::time_point held_rx_{};
  boost::asio::steady_timer timer_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);  // the timer's handler runs only while this lives
};

// A player's controls to the server: controls_t for a road car, else
// drive_t scaled by `scale`; `s` holds the session's token and scene view.
void publishControls(const Bus& bus, const ControlScale& scale, const SessionEntry& s, const std::string& session,
                     int vehicle, const Controls& c, std::int64_t seq);

}  // namespace groundsim::web
