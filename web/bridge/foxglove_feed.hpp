// The Foxglove endpoint's side of the bus: its own LCM subscriptions (on
// the bridge's LCM instance, beside LcmLink's and ContactFeed's), run on the
// LCM thread. A stream's messages are decoded and turned into the
// recorder's JSON only while some Foxglove client subscribes to them
// (setWanted); otherwise only the channel's name is looked at, so that a
// session heard on the bus is advertised (at most one `heard` a second per
// channel). Heartbeats give the sessions the servers list. Every hook runs
// on the LCM thread and must not block: the bridge posts to its I/O thread.
//
// Timestamps: the receive time (ns since the Unix epoch, the bridge's
// system clock when the datagram was handled), not the simulated time. One
// connection mixes sessions whose simulated clocks started at different
// moments and go back to 0 on a reset, and Foxglove's live player orders
// its timeline by this timestamp; the simulated time is in every message
// (`t`, `utime`) for plots against it.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "bridge/foxglove_channels.hpp"

namespace groundsim::web::foxglove {

class Feed {
 public:
  struct Hooks {
    std::function<void(std::vector<std::string> sessions)> listed;  // a heartbeat's sessions
    std::function<void(const std::string& session, Stream s)> heard;
    // a message's JSON; session "" for an event that names none
    std::function<void(const std::string& session, Stream s, std::uint64_t ns, std::shared_ptr<const std::string> json)>
        message;
    std::function<void(const std::string& channel, const std::string& reason)> bad;  // undecodable
  };

  // Subscribes before the LCM thread starts; nullptr: none (tests call handle()).
  Feed(lcm::LCM* lcm, Hooks hooks);
  ~Feed();
  Feed(const Feed&) = delete;
  Feed& operator=(const Feed&) = delete;

  // Any thread: the LCM channels whose messages some client subscribes to.
  void setWanted(std::unordered_set<std::string> lcm_channels);
  // One datagram of `channel` (LCM thread). Never throws.
  void handle(const void* data, int size, const std::string& channel) noexcept;

  std::uint64_t decoded() const { return decoded_; }

 private:
  void onMessage(const lcm::ReceiveBuffer* b, const std::string& channel);
  bool wanted(const std::string& channel);
  void noteHeard(const std::string& channel, const std::string& session, Stream s);

  lcm::LCM* lcm_;
  std::vector<lcm::Subscription*> subs_;
  Hooks hooks_;
  std::mutex mu_;
  std::shared_ptr<const std::unordered_set<std::string>> wanted_;
  // LCM thread: when `heard` was last called per channel
  std::unordered_map<std::string, std::chrono::steady_clock::time_point> heard_at_;
  std::atomic<std::uint64_t> decoded_{0};
};

}  // namespace groundsim::web::foxglove
