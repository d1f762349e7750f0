// Wire types (lcmtypes/) <-> session types. The only place that knows both
// (what clients need of the wire types is in groundsim_protocol).
#pragma once

#include <groundsim/applied_t.hpp>
#include <groundsim/car_state_t.hpp>
#include <groundsim/contact_state_t.hpp>
#include <groundsim/controls_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/replica_t.hpp>
#include <groundsim/request_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/session_info_t.hpp>
#include <groundsim/state_t.hpp>
#include <groundsim/vec_reply_t.hpp>
#include <groundsim/vec_request_t.hpp>

#include <cmath>
#include <cstdint>
#include <optional>

#include "stepping/applied.hpp"
#include "session/types.hpp"

namespace groundsim::net {

// Seconds as microseconds, saturating (no overflow for any double; NaN is 0).
inline std::int64_t toUtime(double t) {
  const double us = t * 1e6;
  if (!(us == us)) return 0;
  if (us >= 9.2e18) return INT64_MAX;
  if (us <= -9.2e18) return INT64_MIN;
  return static_cast<std::int64_t>(std::llround(us));
}

session::Request fromMessage(const groundsim::request_t& m);
session::Drive fromMessage(const groundsim::drive_t& m);
session::CarDrive fromMessage(const groundsim::controls_t& m);
session::VecRequest fromMessage(const groundsim::vec_request_t& m);
// A fleet's traffic between servers (fleet_node.hpp).
session::Applied fromMessage(const groundsim::applied_t& m);
session::Replica fromMessage(const groundsim::replica_t& m);
groundsim::replica_t toMessage(const session::Replica& r);
// Another server's heartbeat listing (no layout).
session::SessionInfo fromMessage(const groundsim::session_info_t& m);

groundsim::state_t toMessage(const session::Frame& f);
// The head of an encoded state_t (its seq and tick, and its epoch, the
// trailing fields), read without decoding the vehicles: a standby reads
// every state of the sessions it keeps (docs/fleet.md). Nothing for bytes
// that are not a whole state_t of this protocol.
struct StateHead {
  std::int64_t seq = 0, tick = 0, epoch = 0;
};
std::optional<StateHead> peekState(const void* data, int size);
// The frame's road cars (f.cars), published beside its state_t.
groundsim::car_state_t toCarMessage(const session::Frame& f);
// The objects and hits of a frame whose scene has contact between bodies.
groundsim::contact_state_t toContactMessage(const session::Frame& f);
// An entry of a session's applied-command log (applied_t).
groundsim::applied_t toMessage(const session::Applied& a);
groundsim::reply_t toMessage(const session::Reply& r, std::int64_t seq);
groundsim::event_t toMessage(const session::Event& e, std::int64_t seq);
// with_layout: a vectorised session's env_layout_t (replies); the
// heartbeat leaves it out to stay small.
groundsim::session_info_t toMessage(const session::SessionInfo& s, bool with_layout = true);
groundsim::env_layout_t toMessage(const experiments::Layout& l);
// The whole reply, every environment in one message: LcmServer splits it
// into parts (protocol/vec_parts.hpp) before publishing.
groundsim::vec_reply_t toMessage(const session::VecReply& r, std::int64_t seq);

}  // namespace groundsim::net
