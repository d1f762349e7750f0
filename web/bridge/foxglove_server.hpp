// The bridge's Foxglove WebSocket endpoint (`groundsim-web --foxglove-port
// N`, docs/logging.md "Views: live in Foxglove"): Foxglove and Lichtblick
// connect to ws://127.0.0.1:N and see one channel per stream of every live
// session (foxglove_channels.hpp), JSON-encoded with the recorder's JSON
// Schemas. A port of its own rather than a path of the page's port:
// Foxglove's connection dialog offers ws://localhost:8765 with no path, the
// endpoint speaks another protocol to other clients with other limits, and
// the page's server (web_server.cpp) stays as it is.
//
// The server only wires its parts, each the owner of its data: the
// listening socket and handshakes (foxglove_listener.hpp), each connection
// and its outbox (foxglove_client.hpp), the clients' subscriptions
// (foxglove_subscriptions.hpp), the channel table (foxglove_channels.hpp)
// and the LCM feed (foxglove_feed.hpp).
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

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bridge/foxglove_channels.hpp"
#include "bridge/foxglove_client.hpp"
#include "bridge/foxglove_feed.hpp"
#include "bridge/foxglove_listener.hpp"
#include "bridge/foxglove_options.hpp"
#include "bridge/foxglove_subscriptions.hpp"

namespace groundsim::web::foxglove {

class Server : private Client::Owner {
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

  using Client = foxglove::Client;  // one WebSocket connection (foxglove_client.hpp)

 private:
  Feed::Hooks feedHooks(std::function<void(const std::string&, const std::string&)> bad);
  void tick();
  // From the feed, posted to the I/O thread.
  void onListed(const std::vector<std::string>& sessions);
  void onHeard(const std::string& session, Stream s);
  void onMessage(const std::string& session, Stream s, std::uint64_t ns, std::shared_ptr<const std::string> json);
  void apply(const ChannelRegistry::Changes& c);
  // From clients (I/O thread): Client::Owner.
  void attach(Client* c) override;
  void detach(Client* c) override;
  void onText(Client* c, const std::string& text) override;
  void refuse(Client* c, const std::string& message) override;
  void updateWanted();

  boost::asio::io_context& io_;
  Options opts_;
  Counters counters_;
  Listener listener_;
  boost::asio::steady_timer ticker_;
  unsigned short port_ = 0;
  std::string server_info_;
  ChannelRegistry registry_;
  Subscriptions subscriptions_;
  Feed feed_;  // last: its hooks use the rest
};

}  // namespace groundsim::web::foxglove
