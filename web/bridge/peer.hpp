// One browser as the hub sees it. The WebSocket session implements it; the
// hub's tests use a recording fake. Both calls happen on the I/O thread and
// never block: a peer queues and writes when its socket is ready.
#pragma once

#include <memory>
#include <string>

namespace groundsim::web {

enum class Slot { State = 0, Lobby = 1, Car = 2 };  // Car: a session's road cars (car_state_t)
inline constexpr int kSlots = 3;

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
};

}  // namespace groundsim::web
