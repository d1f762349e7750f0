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

// Largest encoded vec_reply_t part. LCM's UDP transport sends a message
// that fits one datagram (about 64 KB) unfragmented; a larger one is split
// into fragments and lost whole when any fragment is. A vectorised reply of
// 1,024 environments is ~200 KB, so the server splits it into parts of at
// most this size, each one datagram, and the client accounts for each part.
inline constexpr std::size_t kMaxVecPartBytes = 60000;
// Largest snapshot a restore request carries (a sedan's is a few KB).
inline constexpr std::size_t kMaxSnapshotBytes = 1 << 20;

// Ids and tokens are short (8 and 32 hex digits; client ids are the
// client's choice): anything longer is refused before it is echoed.
inline constexpr std::size_t kMaxIdBytes = 64;

// The server publishes server_status_t on GROUNDSIM_STATUS every
// kHeartbeatPeriod; a client that hears none for kHeartbeatTimeout treats
// the server as gone.
inline constexpr double kHeartbeatPeriod = 1.0;   // s
inline constexpr double kHeartbeatTimeout = 3.0;  // s

}  // namespace groundsim::net
