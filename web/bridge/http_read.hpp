// What the page's server (web_server.cpp) and the Foxglove endpoint
// (foxglove_*.cpp) share of Boost.Beast: the names they use, and one HTTP
// request read from a fresh connection within limits.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace groundsim::web {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

// How much of a request a connection may send, and how long it may take.
struct RequestLimits {
  std::size_t header_bytes = 8192;
  std::size_t body_bytes = 0;
  std::chrono::seconds timeout{10};
};

// A connection's stream and the one request read from it. The owner keeps
// the reader as a member and itself alive in `done` (a shared_from_this):
// a read that fails (timeout, a limit passed, closed) calls nothing, and
// the owner ends with its last reference.
class RequestReader {
 public:
  explicit RequestReader(tcp::socket socket) : stream_(std::move(socket)) {}

  template <class Done>
  void read(const RequestLimits& limits, Done done) {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(limits.header_bytes));
    parser_->body_limit(limits.body_bytes);
    stream_.expires_after(limits.timeout);
    http::async_read(stream_, buffer_, *parser_,
                     [this, done = std::move(done)](beast::error_code ec, std::size_t) mutable {
                       if (!ec) done(parser_->release());
                     });
  }

  beast::tcp_stream& stream() { return stream_; }

 private:
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace groundsim::web
