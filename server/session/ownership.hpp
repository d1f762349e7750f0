// Who owns a session in a fleet (docs/fleet.md). The session service asks
// before it hosts a new session; a lone server has no Ownership and every
// session's epoch stays 0. Implemented at the edge (server/lcm/fleet_node)
// on etcd, so the session layer knows nothing of the fleet's engine.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace groundsim::session {

// The fleet cannot take the session now (its etcd is away, the server is
// draining): the create is refused with ErrorCode::Unavailable, which a
// client meets by creating again.
struct UnavailableError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Ownership {
 public:
  virtual ~Ownership() = default;
  // Claims a fresh session id for this server (a worker calls it while
  // building the session): its epoch (>= 1), or 0 when another server holds
  // the id (the service draws another). Throws UnavailableError when the
  // fleet cannot be reached: the create is refused. `placement` names the create
  // ("<client>/<request>"), so that a fleet counts a placed create and the
  // session it became once.
  virtual std::int64_t claim(const std::string& id, const std::string& placement) = 0;
  // The session ended here (stopped, reclaimed): its claim and its replicas
  // go. Must not block (the receive thread calls it).
  virtual void release(const std::string& id) = 0;
};

}  // namespace groundsim::session
