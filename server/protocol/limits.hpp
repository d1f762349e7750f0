// Bounds of the protocol that every peer knows without asking the server.
#pragma once

#include <cstddef>

namespace groundsim::net {

// Largest scenario a create carries. LCM fragments a large message into
// ~64 KB datagrams; a message of many fragments is lost as a whole when one
// fragment is (socket buffer overflow, LCM's reassembly limits), so a 10 MB
// create got no reply at all. Clients refuse larger creates before sending;
// the server refuses them with ERR_BAD_SCENARIO (its --max-scenario-bytes
// defaults to this and cannot exceed it).
inline constexpr std::size_t kMaxScenarioBytes = 1 << 20;

// Ids and tokens are short (8 and 32 hex digits; client ids are the
// client's choice): anything longer is refused before it is echoed.
inline constexpr std::size_t kMaxIdBytes = 64;

// The server publishes server_status_t on GROUNDSIM_STATUS every
// kHeartbeatPeriod; a client that hears none for kHeartbeatTimeout treats
// the server as gone.
inline constexpr double kHeartbeatPeriod = 1.0;   // s
inline constexpr double kHeartbeatTimeout = 3.0;  // s

}  // namespace groundsim::net
