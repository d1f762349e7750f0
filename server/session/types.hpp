// The session layer's names for what it shares with the re-simulator
// (stepping/types.hpp: modes, requests, frames, replies, events), and the
// transport interface a hosted session publishes through.
#pragma once

#include "stepping/types.hpp"

namespace groundsim::stepping {
struct Applied;  // applied.hpp
}

namespace groundsim::session {

using namespace stepping;  // session::Frame, session::Mode ... name the stepping layer's
using stepping::Drive;     // not the road car's groundsim::Drive

// Implemented by the transport. Called from worker threads and the receive
// thread at once: implementations must be thread-safe and must not block for
// long (they are on the stepping path).
struct AssetWant;  // asset_store.hpp

class Output {
 public:
  virtual ~Output() = default;
  virtual void publishState(const Frame& f) = 0;
  virtual void publishReply(const Reply& r) = 0;
  virtual void publishEvent(const Event& e) = 0;
  virtual void publishVecReply(const VecReply& r) = 0;
  // What a refused create still lacks of one asset, published just before
  // the refusal (ErrorCode::MissingAssets) so that its client can send it.
  virtual void publishAssetWant(const AssetWant& w) = 0;
  // An entry of a session's applied-command log (applied.hpp), from its
  // worker, before the frame it is kept with. Transports without a log
  // ignore it.
  virtual void publishApplied(const Applied&) {}
  // A session's replica for its standbys (fleets only; others ignore it).
  virtual void publishReplica(const Replica&) {}
};

}  // namespace groundsim::session
