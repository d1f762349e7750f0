// Which Foxglove channels exist: one per stream of each live session, with
// the MCAP recorder's topic names and JSON Schemas (protocol/message_json.hpp),
// so a Foxglove layout made on a `groundsim record` file reads a live
// session too. Sessions come from the servers' heartbeats (every session
// they list) and from the bus (a session whose states are heard without a
// heartbeat, e.g. a `groundsim replay`); a session neither listed nor heard
// for kGoneAfter is gone and its channels are unadvertised. A car's or a
// contact scene's extra streams are advertised once heard, since a
// heartbeat does not say whether a session publishes them.
// I/O thread only; time is passed in, so tests drive it.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bridge/foxglove_protocol.hpp"

namespace groundsim::web::foxglove {

enum class Stream {
  State,     // /<id>/state      state_t           every session
  CarState,  // /<id>/car_state  car_state_t       road cars, once heard
  Contact,   // /<id>/contact    contact_state_t   scenes with contact, once heard
  Events,    // /<id>/events     event_t naming the session
  Applied,   // /<id>/applied    applied_t, what changed the simulation and when
  AllEvents  // /events          every event_t (one channel, not per session)
};
inline constexpr int kStreams = 6;

// The LCM channel a stream of a session arrives on, or "" for the bus-wide
// event channel (its messages are always decoded: a few a second at most).
std::string lcmChannel(const std::string& session, Stream s);

class ChannelRegistry {
 public:
  using Clock = std::chrono::steady_clock;
  // heartbeats come every 1 s (0.25 s in a fleet): three missed is gone
  static constexpr std::chrono::seconds kGoneAfter{3};
  // sessions tracked at most: a bus flooded with made-up session ids cannot grow this
  static constexpr std::size_t kMaxSessions = 1024;

  struct Changes {
    std::vector<const Channel*> added;  // valid until the next call that changes the registry
    std::vector<std::uint64_t> removed;
    bool empty() const { return added.empty() && removed.empty(); }
  };

  ChannelRegistry();
  // A heartbeat listed these sessions (ids already validated).
  Changes listed(const std::vector<std::string>& sessions, Clock::time_point now);
  // A message of `s` was heard for `session`.
  Changes heard(const std::string& session, Stream s, Clock::time_point now);
  // Sessions neither listed nor heard for kGoneAfter.
  Changes expire(Clock::time_point now);

  const Channel* find(std::uint64_t id) const;
  std::optional<std::uint64_t> channelOf(const std::string& session, Stream s) const;
  // The session and stream of a channel (session "" for /events).
  std::optional<std::pair<std::string, Stream>> streamOf(std::uint64_t id) const;
  std::vector<const Channel*> all() const;
  std::size_t size() const { return channels_.size(); }
  std::size_t sessions() const { return sessions_.size(); }

 private:
  struct Session {
    Clock::time_point last{};
    std::optional<std::uint64_t> ids[kStreams];
  };
  // Adds the session (if room) and `s`'s channel if it has none.
  void ensure(const std::string& session, Stream s, Clock::time_point now, Changes& out);

  std::uint64_t next_id_ = 1;
  std::map<std::uint64_t, Channel> channels_;  // node-based: pointers stay valid until erased
  std::map<std::uint64_t, std::pair<std::string, Stream>> streams_;
  std::map<std::string, Session> sessions_;
};

}  // namespace groundsim::web::foxglove
