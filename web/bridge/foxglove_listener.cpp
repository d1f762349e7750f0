#include "bridge/foxglove_listener.hpp"

#include <cstdio>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "bridge/foxglove_client.hpp"
#include "bridge/foxglove_protocol.hpp"
#include "bridge/http_read.hpp"
#include "bridge/listen.hpp"

namespace groundsim::web::foxglove {

namespace {

// Reads the HTTP upgrade request and either hands the socket to a Client
// (with the subprotocol it asked for) or answers why not.
class Handshake : public std::enable_shared_from_this<Handshake> {
 public:
  using Accept = std::function<void(tcp::socket, http::request<http::string_body>, std::string subprotocol)>;
  using Refused = std::function<void(const std::string& why)>;
  Handshake(tcp::socket s, Accept accept, Refused refused)
      : reader_(std::move(s)), accept_(std::move(accept)), refused_(std::move(refused)) {}

  // an upgrade request has no body; a client gets 10 s to send it
  void read() {
    reader_.read({.header_bytes = 8192, .body_bytes = 0, .timeout = std::chrono::seconds(10)},
                 [self = shared_from_this()](http::request<http::string_body> req) { self->handle(std::move(req)); });
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
    reader_.stream().expires_never();
    accept_(reader_.stream().release_socket(), std::move(req), *chosen);
  }

  void write(std::shared_ptr<http::response<http::string_body>> res) {
    res->prepare_payload();
    http::async_write(reader_.stream(), *res, [self = shared_from_this(), res](beast::error_code, std::size_t) {
      beast::error_code e;
      self->reader_.stream().socket().shutdown(tcp::socket::shutdown_send, e);
    });
  }

  RequestReader reader_;
  Accept accept_;
  Refused refused_;
};

}  // namespace

Listener::Listener(asio::io_context& io, const Options& opts, Counters& counters, Accepted accepted)
    : acceptor_(io), opts_(opts), counters_(counters), accepted_(std::move(accepted)) {}

unsigned short Listener::listen(const std::string& address, unsigned short port) {
  const unsigned short bound = listenOn(acceptor_, address, port);
  accept();
  return bound;
}

void Listener::close() {
  beast::error_code ec;
  acceptor_.close(ec);
}

void Listener::accept() {
  acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (!ec) {
      socket.set_option(tcp::no_delay(true), ec);
      socket.set_option(asio::socket_base::send_buffer_size(opts_.send_buffer), ec);
      const std::string who = peerName(socket);
      std::make_shared<Handshake>(std::move(socket), accepted_,
                                  [this, who](const std::string& why) { refused(who, why); })
          ->read();
    }
    if (acceptor_.is_open()) accept();
  });
}

void Listener::refused(const std::string& who, const std::string& why) {
  ++counters_.handshakes_refused;
  if (opts_.log)
    std::fprintf(stderr, "groundsim-web: foxglove connection from %s refused: %s\n", who.c_str(), why.c_str());
}

}  // namespace groundsim::web::foxglove
