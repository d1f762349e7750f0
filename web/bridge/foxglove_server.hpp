// The bridge's Foxglove WebSocket endpoint (`groundsim-web --foxglove-port
// N`, docs/logging.md "Views: live in Foxglove"): Foxglove and Lichtblick
// connect to ws://127.0.0.1:N and see one channel per stream of every live
// session (foxglove_channels.hpp), JSON-encoded with the recorder's JSON
// Schemas. A port of its own rather than a path of the page's port:
// Foxglove's connection dialog offers ws://localhost:8765 with no path, the
// endpoint speaks another protocol to other clients with other limits, and
// the page's server (web_server.cpp) stays as it is.
//
// Per client: messages flow only on the channels it subscribes to; its
// outbox keeps the protocol's control messages (serverInfo, advertise,
// unadvertise, status) in order and never drops them (a client that leaves
// kMaxControl of them unread is closed, as the Foxglove SDK does), and its
// data messages in a bounded queue where the oldest is dropped when a new
// one comes (the SDK's policy; counted in /metrics, and the client is told
// by a status warning at most every 5 s). A bad client message gets a
// status error naming the field and changes nothing, and so does one over
// 64 KiB (read and dropped as it comes); one beyond 16 MiB closes that
// client only (1009). One I/O thread, shared with
// the page's server; nothing here blocks it.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bridge/foxglove_channels.hpp"
#include "bridge/foxglove_feed.hpp"

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

class Server {
 public:
  // Subscribes on `bus` (before its LCM thread starts; nullptr: none, for
  // tests); `bad` hears undecodable messages (the bridge counts them).
  Server(boost::asio::io_context& io, lcm::LCM* bus, Options opts,
         std::function<void(const std::string& channel, const std::string& reason)> bad = {});
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Throws boost::system::system_error when the address cannot be bound.
  void listen(const std::string& address, unsigned short port);
  unsigned short port() const { return port_; }

  // I/O thread: the Prometheus text of the endpoint's gauges and counters.
  std::string metrics() const;
  const Counters& counters() const { return counters_; }

  class Client;  // one WebSocket connection (foxglove_server.cpp)

 private:
  friend class Client;
  struct ClientState {
    std::map<std::uint32_t, std::uint64_t> subs;        // subscription id -> channel
    std::map<std::uint64_t, std::uint32_t> by_channel;  // channel -> subscription id
  };

  void accept();
  void tick();
  // From the feed, posted to the I/O thread.
  void onListed(const std::vector<std::string>& sessions);
  void onHeard(const std::string& session, Stream s);
  void onMessage(const std::string& session, Stream s, std::uint64_t ns, std::shared_ptr<const std::string> json);
  void apply(const ChannelRegistry::Changes& c);
  void deliver(std::uint64_t channel, std::uint64_t ns, const std::shared_ptr<const std::string>& json);
  // From clients (I/O thread).
  void attach(Client* c);
  void detach(Client* c);
  void onText(Client* c, const std::string& text);
  void refuse(Client* c, const std::string& message);
  void updateWanted();

  boost::asio::io_context& io_;
  Options opts_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer ticker_;
  unsigned short port_ = 0;
  std::string server_info_;
  ChannelRegistry registry_;
  std::map<Client*, ClientState> clients_;
  Counters counters_;
  Feed feed_;  // last: its hooks use the rest
};

}  // namespace groundsim::web::foxglove
