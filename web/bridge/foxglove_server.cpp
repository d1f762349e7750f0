#include "bridge/foxglove_server.hpp"

#include <chrono>
#include <cstdio>

#include <boost/asio/post.hpp>

#include "protocol/metrics_text.hpp"
#include "protocol/message_json.hpp"

namespace groundsim::web::foxglove {

namespace asio = boost::asio;
namespace http = boost::beast::http;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

Server::Server(asio::io_context& io, lcm::LCM* bus, Options opts,
               std::function<void(const std::string&, const std::string&)> bad)
    : io_(io),
      opts_(opts),
      listener_(io, opts_, counters_,
                [this](tcp::socket s, http::request<http::string_body> req, std::string subprotocol) {
                  Client::Owner& owner = *this;  // a private base: converted here, where it is accessible
                  std::make_shared<Client>(std::move(s), std::move(subprotocol), opts_, counters_, owner)
                      ->start(std::move(req));
                }),
      ticker_(io),
      subscriptions_(registry_, counters_),
      feed_(bus, feedHooks(std::move(bad))) {
  const auto started = std::chrono::duration_cast<std::chrono::milliseconds>(
                           std::chrono::system_clock::now().time_since_epoch())
                           .count();
  server_info_ = serverInfo(
      "groundsim-web", std::to_string(started),
      {{"timestamps", "receive time: ns since the Unix epoch when the bridge heard the message; the simulated "
                      "time is the message's t (s) and utime (us)"},
       {"topics", "/<session>/state, /car_state, /contact, /events, /applied and /events: groundsim record's "
                  "topics and schemas (docs/logging.md)"},
       {"json_precision", record::precisionName()}});
  tick();
}

Server::~Server() {
  ticker_.cancel();
  listener_.close();
}

// The feed's news, posted to the I/O thread.
Feed::Hooks Server::feedHooks(std::function<void(const std::string&, const std::string&)> bad) {
  return Feed::Hooks{
      [this](std::vector<std::string> ids) { asio::post(io_, [this, ids = std::move(ids)] { onListed(ids); }); },
      [this](const std::string& session, Stream s) { asio::post(io_, [this, session, s] { onHeard(session, s); }); },
      [this](const std::string& session, Stream s, std::uint64_t ns, std::shared_ptr<const std::string> json) {
        asio::post(io_, [this, session, s, ns, json = std::move(json)] { onMessage(session, s, ns, json); });
      },
      std::move(bad)};
}

void Server::listen(const std::string& address, unsigned short port) { port_ = listener_.listen(address, port); }

// 1 Hz: sessions gone quiet lose their channels.
void Server::tick() {
  apply(registry_.expire(Clock::now()));
  ticker_.expires_after(std::chrono::seconds(1));
  ticker_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) tick();
  });
}

void Server::onListed(const std::vector<std::string>& sessions) { apply(registry_.listed(sessions, Clock::now())); }

void Server::onHeard(const std::string& session, Stream s) { apply(registry_.heard(session, s, Clock::now())); }

void Server::onMessage(const std::string& session, Stream s, std::uint64_t ns,
                       std::shared_ptr<const std::string> json) {
  if (s == Stream::Events) {
    subscriptions_.deliver(*registry_.channelOf("", Stream::AllEvents), ns, json);
    if (session.empty()) return;
  }
  if (const auto ch = registry_.channelOf(session, s)) subscriptions_.deliver(*ch, ns, json);
}

void Server::apply(const ChannelRegistry::Changes& ch) {
  if (ch.empty()) return;
  std::shared_ptr<const std::string> added, removed;
  if (!ch.added.empty()) added = std::make_shared<const std::string>(advertise(ch.added));
  if (!ch.removed.empty()) removed = std::make_shared<const std::string>(unadvertise(ch.removed));
  // a client's subscriptions of a channel that goes end before it hears so
  const bool subscriptions_ended = subscriptions_.channelsGone(ch.removed);
  if (removed) subscriptions_.broadcast(removed);
  if (added) subscriptions_.broadcast(added);
  if (subscriptions_ended) updateWanted();
}

void Server::attach(Client* c) {
  subscriptions_.add(c);
  c->markAttached();
  ++counters_.connections;
  c->sendControl(std::make_shared<const std::string>(server_info_));
  c->sendControl(std::make_shared<const std::string>(advertise(registry_.all())));
  if (opts_.log)
    std::fprintf(stderr, "groundsim-web: foxglove client %s connected (%s)\n", c->name().c_str(),
                 c->subprotocol().c_str());
}

void Server::detach(Client* c) {
  if (!subscriptions_.contains(c)) return;
  if (subscriptions_.remove(c)) updateWanted();
  if (opts_.log) std::fprintf(stderr, "groundsim-web: foxglove client %s left\n", c->name().c_str());
}

void Server::refuse(Client* c, const std::string& message) { subscriptions_.refuse(c, message); }

void Server::onText(Client* c, const std::string& text) {
  if (subscriptions_.onText(c, text)) updateWanted();
}

void Server::updateWanted() { feed_.setWanted(subscriptions_.wanted()); }

std::string Server::metrics() const {
  net::MetricsText m;
  m.single("groundsim_web_foxglove_clients", "gauge", "Foxglove WebSocket clients connected (--foxglove-port).",
           static_cast<std::uint64_t>(subscriptions_.clients()));
  m.single("groundsim_web_foxglove_channels", "gauge", "Channels advertised to Foxglove clients.",
           static_cast<std::uint64_t>(registry_.size()));
  m.single("groundsim_web_foxglove_subscriptions", "gauge", "Subscriptions of the Foxglove clients connected.",
           subscriptions_.count());
  m.single("groundsim_web_foxglove_connections_total", "counter", "Foxglove WebSocket handshakes accepted.",
           counters_.connections);
  m.single("groundsim_web_foxglove_handshakes_refused_total", "counter",
           "Connections to the Foxglove port refused: no foxglove.sdk.v1 or foxglove.websocket.v1 subprotocol "
           "offered, or not a WebSocket upgrade.",
           counters_.handshakes_refused);
  m.single("groundsim_web_foxglove_messages_sent_total", "counter", "Data messages written to Foxglove clients.",
           counters_.messages_sent);
  m.single("groundsim_web_foxglove_messages_dropped_total", "counter",
           "Data messages dropped from slow Foxglove clients' outboxes (the oldest, when a full outbox gets a new "
           "one).",
           counters_.messages_dropped);
  m.single("groundsim_web_foxglove_client_errors_total", "counter",
           "Foxglove client messages refused with a status error (or a close, for a frame over the hard limit).",
           counters_.client_errors);
  m.single("groundsim_web_foxglove_clients_closed_total", "counter",
           "Foxglove clients closed by the bridge: a frame over the hard limit, or control messages left unread.",
           counters_.clients_closed);
  m.single("groundsim_web_foxglove_sent_bytes_total", "counter", "Bytes of WebSocket payloads written to Foxglove "
           "clients.", counters_.bytes_sent);
  return m.take();
}

}  // namespace groundsim::web::foxglove
