#include "bridge/foxglove_server.hpp"

#include <array>
#include <cstdio>
#include <deque>
#include <limits>
#include <optional>
#include <unordered_set>

#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "bridge/listen.hpp"
#include "protocol/metrics_text.hpp"
#include "protocol/message_json.hpp"

namespace groundsim::web::foxglove {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

namespace {

// bytes read at a time from a client
constexpr std::size_t kReadChunk = 16 << 10;
// a slow client is told of its dropped messages at most this often
constexpr auto kDropWarningEvery = std::chrono::seconds(5);

std::string peerName(const tcp::socket& s) {
  beast::error_code ec;
  const auto ep = s.remote_endpoint(ec);
  return ec ? "?" : ep.address().to_string() + ":" + std::to_string(ep.port());
}

}  // namespace

// ---- one connection -----------------------------------------------------------

class Server::Client : public std::enable_shared_from_this<Server::Client> {
 public:
  Client(tcp::socket socket, Server& server, std::string subprotocol)
      : ws_(std::move(socket)), server_(server), subprotocol_(std::move(subprotocol)) {
    name_ = peerName(ws_.next_layer().socket());
  }

  void start(http::request<http::string_body> req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([p = subprotocol_](websocket::response_type& res) {
      res.set(http::field::sec_websocket_protocol, p);
      res.set(http::field::server, "groundsim-web");
    }));
    // the limits are read()'s own (a message is read piecewise and dropped past max_message_bytes)
    ws_.read_message_max(std::numeric_limits<std::size_t>::max());
    ws_.async_accept(req, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->open_ = true;
      self->server_.attach(self.get());
      self->read();
    });
  }

  const std::string& name() const { return name_; }
  const std::string& subprotocol() const { return subprotocol_; }

  // In order, never dropped; a client that leaves max_control of them unread is closed.
  void sendControl(std::shared_ptr<const std::string> text) {
    if (!open_) return;
    if (control_.size() >= server_.opts_.max_control) {
      if (server_.opts_.log)
        std::fprintf(stderr, "groundsim-web: foxglove client %s left %zu control messages unread: closing\n",
                     name_.c_str(), control_.size());
      ++server_.counters_.clients_closed;
      // not from inside the server's loop over its clients: later, on its own
      asio::post(ws_.get_executor(), [self = shared_from_this()] { self->close(); });
      open_ = false;  // nothing more is queued; close() still detaches
      return;
    }
    control_.push_back(std::move(text));
    write();
  }

  // Bounded: the oldest data message goes when the outbox is full.
  void sendData(std::uint32_t subscription, std::uint64_t ns, std::shared_ptr<const std::string> json) {
    if (!open_) return;
    if (data_.size() >= server_.opts_.outbox) {
      data_.pop_front();
      ++dropped_;
      ++dropped_unreported_;
      ++server_.counters_.messages_dropped;
    }
    data_.push_back(Data{dataHeader(subscription, ns), std::move(json), subscription});
    write();
  }

  // Drops what waits for a subscription that ends (its id may be reused).
  void forget(std::uint32_t subscription) {
    std::erase_if(data_, [&](const Data& d) { return d.subscription == subscription; });
  }

  // The bridge closes this client (I/O thread; from outside its own handlers only).
  void close() {
    const bool was_attached = attached_;
    attached_ = false;
    open_ = false;
    control_.clear();
    data_.clear();
    if (was_attached) server_.detach(this);
    beast::error_code ec;
    ws_.next_layer().socket().shutdown(tcp::socket::shutdown_both, ec);
    ws_.next_layer().socket().close(ec);
  }
  void markAttached() { attached_ = true; }

 private:
  struct Data {
    std::array<std::uint8_t, kDataHeaderBytes> header;
    std::shared_ptr<const std::string> payload;
    std::uint32_t subscription;
  };

  // Piece by piece, so that a message over max_message_bytes is read and
  // dropped as it comes (never held whole) and answered with a status error.
  // One over max_frame_bytes closes the client: the bridge says why in a
  // close frame (1009) and reads on, dropping what comes, until the client's
  // close frame (or Beast's close timeout), rather than let Beast's own
  // limit close the socket at once: Boost 1.74's teardown resets a
  // connection whose client is still sending, and the client then sees
  // 1006 instead of the reason.
  void read() {
    ws_.async_read_some(buffer_, kReadChunk, [self = shared_from_this()](beast::error_code ec, std::size_t n) {
      if (ec) return self->close();
      if (self->draining_) {
        self->buffer_.consume(self->buffer_.size());
        return self->read();
      }
      if (!self->open_) return;
      self->message_bytes_ += n;
      if (self->message_bytes_ > self->server_.opts_.max_message_bytes) self->buffer_.consume(self->buffer_.size());
      if (self->message_bytes_ > self->server_.opts_.max_frame_bytes) return self->tooBig();
      if (self->ws_.is_message_done()) {
        if (!self->ws_.got_text()) {
          self->server_.refuse(self.get(), "refused binary message: this server takes no client publishing "
                                           "(no clientPublish capability) nor service calls");
        } else if (self->message_bytes_ > self->server_.opts_.max_message_bytes) {
          self->server_.refuse(self.get(), "refused message of " + std::to_string(self->message_bytes_) +
                                               " bytes: at most " +
                                               std::to_string(self->server_.opts_.max_message_bytes));
        } else {
          self->server_.onText(self.get(), beast::buffers_to_string(self->buffer_.data()));
        }
        self->buffer_.consume(self->buffer_.size());
        self->message_bytes_ = 0;
      }
      if (self->open_) self->read();
    });
  }

  void tooBig() {
    ++server_.counters_.clients_closed;
    ++server_.counters_.client_errors;
    if (server_.opts_.log)
      std::fprintf(stderr, "groundsim-web: foxglove client %s sent a message over %zu bytes: closing\n",
                   name_.c_str(), server_.opts_.max_frame_bytes);
    // nothing more for it; the server forgets it now (not inside one of its loops: a read handler)
    open_ = false;
    draining_ = true;
    control_.clear();
    data_.clear();
    if (attached_) {
      attached_ = false;
      server_.detach(this);
    }
    const std::string why = "message over " + std::to_string(server_.opts_.max_frame_bytes) + " bytes";
    ws_.async_close(websocket::close_reason(websocket::close_code::too_big, why),
                    [self = shared_from_this()](beast::error_code) {});
    read();
  }

  void write() {
    if (writing_ || !open_) return;
    // drops are told when the socket takes more again: the count then covers the whole stall
    const auto now = Clock::now();
    if (dropped_unreported_ && now - last_drop_warning_ >= kDropWarningEvery) {
      last_drop_warning_ = now;
      control_.push_back(std::make_shared<const std::string>(
          status(Level::Warning, "dropped " + std::to_string(dropped_unreported_) +
                                     " messages: this client reads slower than they come (of " +
                                     std::to_string(server_.opts_.outbox) + " waiting, the oldest go first)")));
      dropped_unreported_ = 0;
    }
    auto done = [self = shared_from_this()](beast::error_code ec, std::size_t n) {
      self->writing_ = false;
      self->text_.reset();
      self->current_.payload.reset();
      self->server_.counters_.bytes_sent += n;
      if (ec) return self->close();
      self->write();
    };
    if (!control_.empty()) {
      text_ = std::move(control_.front());
      control_.pop_front();
      writing_ = true;
      ws_.text(true);
      ws_.async_write(asio::buffer(*text_), std::move(done));
      return;
    }
    if (data_.empty()) return;
    current_ = std::move(data_.front());
    data_.pop_front();
    writing_ = true;
    ++server_.counters_.messages_sent;
    ws_.binary(true);
    // the header and the shared JSON as one message: the JSON is not copied per client
    const std::array<asio::const_buffer, 2> bufs{asio::buffer(current_.header), asio::buffer(*current_.payload)};
    ws_.async_write(bufs, std::move(done));
  }

  websocket::stream<beast::tcp_stream> ws_;
  Server& server_;
  std::string subprotocol_, name_;
  beast::flat_buffer buffer_;
  std::deque<std::shared_ptr<const std::string>> control_;
  std::deque<Data> data_;
  std::shared_ptr<const std::string> text_;  // being written
  Data current_{};                           // being written
  bool writing_ = false, open_ = false, attached_ = false;
  bool draining_ = false;  // closing for a message too big: what comes is dropped
  std::uint64_t dropped_ = 0, dropped_unreported_ = 0;
  std::size_t message_bytes_ = 0;  // of the message being read
  Clock::time_point last_drop_warning_{};
};

// ---- the handshake ------------------------------------------------------------

namespace {

// Reads the HTTP upgrade request and either hands the socket to a Client
// (with the subprotocol it asked for) or answers why not.
class Handshake : public std::enable_shared_from_this<Handshake> {
 public:
  using Accept = std::function<void(tcp::socket, http::request<http::string_body>, std::string subprotocol)>;
  using Refused = std::function<void(const std::string& why)>;
  Handshake(tcp::socket s, Accept accept, Refused refused)
      : stream_(std::move(s)), accept_(std::move(accept)), refused_(std::move(refused)) {}

  void read() {
    parser_.emplace();
    parser_->header_limit(8192);
    parser_->body_limit(0);
    stream_.expires_after(std::chrono::seconds(10));
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;
      self->handle(self->parser_->release());
    });
  }

 private:
  void handle(http::request<http::string_body> req) {
    auto res = std::make_shared<http::response<http::string_body>>();
    res->version(req.version());
    res->keep_alive(false);
    res->set(http::field::server, "groundsim-web");
    res->set(http::field::content_type, "text/plain; charset=utf-8");
    const std::string offer = std::string(kSdkSubprotocol) + " or " + kLegacySubprotocol;
    if (!websocket::is_upgrade(req)) {
      res->result(http::status::upgrade_required);
      res->set(http::field::upgrade, "websocket");
      res->body() = "groundsim-web's Foxglove WebSocket endpoint: connect a Foxglove WebSocket client (subprotocol " +
                    offer + ") to ws://<this address>/\n";
      refused_("not a WebSocket upgrade");
      return write(res);
    }
    std::vector<std::string_view> headers;
    const auto [first, last] = req.equal_range(http::field::sec_websocket_protocol);
    for (auto f = first; f != last; ++f) headers.emplace_back(f->value().data(), f->value().size());
    const auto chosen = chooseSubprotocol(headers);
    if (!chosen) {
      std::string asked;
      for (auto h : headers) asked += (asked.empty() ? "" : ", ") + std::string(h);
      // as the Foxglove SDK refuses a connection without its subprotocol: 400 and why
      res->result(http::status::bad_request);
      res->body() = "Sec-WebSocket-Protocol must offer " + offer + " (offered: " +
                    (asked.empty() ? std::string("none") : asked) + ")\n";
      refused_("subprotocol " + (asked.empty() ? std::string("none") : asked));
      return write(res);
    }
    stream_.expires_never();
    accept_(stream_.release_socket(), std::move(req), *chosen);
  }

  void write(std::shared_ptr<http::response<http::string_body>> res) {
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code, std::size_t) {
      beast::error_code e;
      self->stream_.socket().shutdown(tcp::socket::shutdown_send, e);
    });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  Accept accept_;
  Refused refused_;
};

}  // namespace

// ---- the server ---------------------------------------------------------------

Server::Server(asio::io_context& io, lcm::LCM* bus, Options opts,
               std::function<void(const std::string&, const std::string&)> bad)
    : io_(io),
      opts_(opts),
      acceptor_(io),
      ticker_(io),
      feed_(bus, Feed::Hooks{
                     [this](std::vector<std::string> ids) {
                       asio::post(io_, [this, ids = std::move(ids)] { onListed(ids); });
                     },
                     [this](const std::string& session, Stream s) {
                       asio::post(io_, [this, session, s] { onHeard(session, s); });
                     },
                     [this](const std::string& session, Stream s, std::uint64_t ns,
                            std::shared_ptr<const std::string> json) {
                       asio::post(io_, [this, session, s, ns, json = std::move(json)] {
                         onMessage(session, s, ns, json);
                       });
                     },
                     std::move(bad)}) {
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
  beast::error_code ec;
  acceptor_.close(ec);
}

void Server::listen(const std::string& address, unsigned short port) {
  port_ = listenOn(acceptor_, address, port);
  accept();
}

void Server::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!ec) {
      socket.set_option(tcp::no_delay(true), ec);
      socket.set_option(asio::socket_base::send_buffer_size(opts_.send_buffer), ec);
      const std::string who = peerName(socket);
      std::make_shared<Handshake>(
          std::move(socket),
          [this](tcp::socket s, http::request<http::string_body> req, std::string subprotocol) {
            std::make_shared<Client>(std::move(s), *this, std::move(subprotocol))->start(std::move(req));
          },
          [this, who](const std::string& why) {
            ++counters_.handshakes_refused;
            if (opts_.log) std::fprintf(stderr, "groundsim-web: foxglove connection from %s refused: %s\n",
                                        who.c_str(), why.c_str());
          })
          ->read();
    }
    if (acceptor_.is_open()) accept();
  });
}

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
    deliver(*registry_.channelOf("", Stream::AllEvents), ns, json);
    if (session.empty()) return;
  }
  if (const auto ch = registry_.channelOf(session, s)) deliver(*ch, ns, json);
}

void Server::deliver(std::uint64_t channel, std::uint64_t ns, const std::shared_ptr<const std::string>& json) {
  for (auto& [c, st] : clients_) {
    const auto it = st.by_channel.find(channel);
    if (it != st.by_channel.end()) c->sendData(it->second, ns, json);
  }
}

void Server::apply(const ChannelRegistry::Changes& ch) {
  if (ch.empty()) return;
  std::shared_ptr<const std::string> added, removed;
  if (!ch.added.empty()) added = std::make_shared<const std::string>(advertise(ch.added));
  if (!ch.removed.empty()) removed = std::make_shared<const std::string>(unadvertise(ch.removed));
  bool subscriptions_ended = false;
  for (auto& [c, st] : clients_) {
    for (const std::uint64_t id : ch.removed) {
      // as the SDK does: a channel that goes takes its subscriptions with it
      const auto it = st.by_channel.find(id);
      if (it == st.by_channel.end()) continue;
      c->forget(it->second);
      st.subs.erase(it->second);
      st.by_channel.erase(it);
      subscriptions_ended = true;
    }
    if (removed) c->sendControl(removed);
    if (added) c->sendControl(added);
  }
  if (subscriptions_ended) updateWanted();
}

void Server::attach(Client* c) {
  clients_[c] = ClientState{};
  c->markAttached();
  ++counters_.connections;
  c->sendControl(std::make_shared<const std::string>(server_info_));
  c->sendControl(std::make_shared<const std::string>(advertise(registry_.all())));
  if (opts_.log)
    std::fprintf(stderr, "groundsim-web: foxglove client %s connected (%s)\n", c->name().c_str(),
                 c->subprotocol().c_str());
}

void Server::detach(Client* c) {
  const auto it = clients_.find(c);
  if (it == clients_.end()) return;
  const bool had = !it->second.subs.empty();
  clients_.erase(it);
  if (had) updateWanted();
  if (opts_.log) std::fprintf(stderr, "groundsim-web: foxglove client %s left\n", c->name().c_str());
}

void Server::refuse(Client* c, const std::string& message) {
  ++counters_.client_errors;
  c->sendControl(std::make_shared<const std::string>(status(Level::Error, message)));
}

void Server::onText(Client* c, const std::string& text) {
  const auto it = clients_.find(c);
  if (it == clients_.end()) return;
  ClientState& st = it->second;
  const ClientMessage m = parseClientMessage(text);
  if (const auto* e = std::get_if<ClientError>(&m)) return refuse(c, e->text());
  bool changed = false;
  if (const auto* sub = std::get_if<Subscribe>(&m)) {
    // each entry on its own: a bad one is refused, the others still count (as the SDK does)
    for (std::size_t i = 0; i < sub->subscriptions.size(); ++i) {
      const Subscription& s = sub->subscriptions[i];
      const std::string at = "/subscriptions/" + std::to_string(i);
      if (!registry_.find(s.channel)) {
        refuse(c, "refused " + at + "/channelId: unknown channel " + std::to_string(s.channel));
      } else if (st.subs.count(s.id)) {
        refuse(c, "refused " + at + "/id: subscription " + std::to_string(s.id) + " is in use (channel " +
                      std::to_string(st.subs[s.id]) + ")");
      } else if (const auto b = st.by_channel.find(s.channel); b != st.by_channel.end()) {
        refuse(c, "refused " + at + "/channelId: channel " + std::to_string(s.channel) +
                      " is already subscribed (subscription " + std::to_string(b->second) + ")");
      } else {
        st.subs[s.id] = s.channel;
        st.by_channel[s.channel] = s.id;
        changed = true;
      }
    }
  } else if (const auto* un = std::get_if<Unsubscribe>(&m)) {
    for (std::size_t i = 0; i < un->ids.size(); ++i) {
      const auto s = st.subs.find(un->ids[i]);
      if (s == st.subs.end()) {
        refuse(c, "refused /subscriptionIds/" + std::to_string(i) + ": unknown subscription " +
                      std::to_string(un->ids[i]));
        continue;
      }
      c->forget(s->first);
      st.by_channel.erase(s->second);
      st.subs.erase(s);
      changed = true;
    }
  }
  if (changed) updateWanted();
}

void Server::updateWanted() {
  std::unordered_set<std::string> wanted;
  for (const auto& [c, st] : clients_)
    for (const auto& [channel, sub] : st.by_channel)
      if (const auto s = registry_.streamOf(channel)) {
        const std::string lcm = lcmChannel(s->first, s->second);
        if (!lcm.empty()) wanted.insert(lcm);
      }
  feed_.setWanted(std::move(wanted));
}

std::string Server::metrics() const {
  net::MetricsText m;
  std::uint64_t subscriptions = 0;
  for (const auto& [c, st] : clients_) subscriptions += st.subs.size();
  m.single("groundsim_web_foxglove_clients", "gauge", "Foxglove WebSocket clients connected (--foxglove-port).",
           static_cast<std::uint64_t>(clients_.size()));
  m.single("groundsim_web_foxglove_channels", "gauge", "Channels advertised to Foxglove clients.",
           static_cast<std::uint64_t>(registry_.size()));
  m.single("groundsim_web_foxglove_subscriptions", "gauge", "Subscriptions of the Foxglove clients connected.",
           subscriptions);
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
