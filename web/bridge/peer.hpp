// One browser as the hub sees it. The WebSocket session implements it; the
// hub's tests use a recording fake. Both calls happen on the I/O thread and
// never block: a peer queues and writes when its socket is ready.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace groundsim::web {

// Car: a session's road cars (car_state_t); Contact: its objects and hits (contact_state_t)
enum class Slot { State = 0, Lobby = 1, Car = 2, Contact = 3 };
inline constexpr int kSlots = 4;

// What a browser's outbox has done, for the browser itself (the pong) and
// tests: states are counted from its connection on.
struct PeerStats {
  std::uint64_t states_sent = 0;     // state messages written (or being written) to the socket
  std::uint64_t states_skipped = 0;  // replaced in the newest-only slot by a newer state before being written
  std::size_t queued = 0;            // ordered messages waiting
  std::size_t waiting_bytes = 0;     // bytes waiting in the bridge: the ordered queue and the slots
  int send_buffer = 0;               // the socket's SO_SNDBUF as set (bytes; Linux books twice that)
};

class Peer {
 public:
  virtual ~Peer() = default;
  // In order, never dropped. A peer whose ordered queue grows past its
  // bound (a browser that stopped reading) is disconnected.
  virtual void send(std::shared_ptr<const std::string> msg) = 0;
  // Only the newest message per slot is kept: a slow browser skips stale
  // states instead of falling behind.
  virtual void sendLatest(Slot slot, std::shared_ptr<const std::string> msg) = 0;
  virtual std::string describe() const = 0;
  virtual PeerStats stats() const = 0;
};

}  // namespace groundsim::web
