// The Foxglove endpoint's limits and counters (foxglove_server.hpp), shared
// by its parts: the listener, each client, the subscriptions.
#pragma once

#include <cstddef>
#include <cstdint>

namespace groundsim::web::foxglove {

struct Options {
  std::size_t outbox = 1024;                // data messages a client may fall behind by (oldest dropped beyond)
  std::size_t max_control = 1024;           // control messages unread before a client is closed
  std::size_t max_message_bytes = 64 << 10;  // larger messages get a status error (read and dropped piecewise)
  std::size_t max_frame_bytes = 16 << 20;    // larger messages close the client (1009, message too big)
  int send_buffer = 64 << 10;                // the socket's SO_SNDBUF (Linux books twice that)
  bool log = true;                           // connections and refusals on stderr
};

// Since start, on the I/O thread (GET /metrics).
struct Counters {
  std::uint64_t connections = 0;         // handshakes accepted
  std::uint64_t handshakes_refused = 0;  // no subprotocol of ours offered, or not a WebSocket upgrade
  std::uint64_t messages_sent = 0;       // data messages written to clients
  std::uint64_t messages_dropped = 0;    // dropped from slow clients' outboxes, oldest first
  std::uint64_t client_errors = 0;       // client messages answered with a status error
  std::uint64_t clients_closed = 0;      // closed by the bridge: a frame too big, or control messages unread
  std::uint64_t bytes_sent = 0;          // WebSocket payloads written
};

}  // namespace groundsim::web::foxglove
