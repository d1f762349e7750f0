#include "fleet/http.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

namespace groundsim::fleet {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

Url parseUrl(const std::string& url) {
  std::string rest = url;
  if (rest.rfind("https://", 0) == 0) throw std::invalid_argument("etcd endpoint " + url + ": https is not supported");
  if (rest.rfind("http://", 0) == 0) rest = rest.substr(7);
  while (!rest.empty() && rest.back() == '/') rest.pop_back();
  Url u;
  std::size_t colon;
  if (!rest.empty() && rest.front() == '[') {
    auto close = rest.find(']');
    if (close == std::string::npos) throw std::invalid_argument("etcd endpoint " + url + ": bad IPv6 address");
    u.host = rest.substr(1, close - 1);
    colon = rest.find(':', close);
  } else {
    colon = rest.rfind(':');
    u.host = rest.substr(0, colon);
  }
  if (colon == std::string::npos) {
    u.port = "2379";
  } else {
    u.port = rest.substr(colon + 1);
  }
  if (u.host.empty() || u.port.empty() || u.port.find_first_not_of("0123456789") != std::string::npos ||
      rest.find('/') != std::string::npos)
    throw std::invalid_argument("etcd endpoint " + url + ": expected http://host:port");
  return u;
}

namespace {

// Runs ioc until the pending operation completed (done) or the deadline;
// on the deadline the socket closes, so the operation ends as aborted.
void runUntil(net::io_context& ioc, const bool& done, std::chrono::steady_clock::time_point deadline,
              beast::tcp_stream& stream) {
  while (!done) {
    auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      beast::error_code ignored;
      stream.socket().close(ignored);
      ioc.restart();
      ioc.run();
      return;
    }
    ioc.restart();
    ioc.run_for(deadline - now);
  }
}

std::string reason(const beast::error_code& ec, std::chrono::milliseconds timeout) {
  if (ec == beast::error::timeout || ec == net::error::operation_aborted)
    return "timeout after " + std::to_string(timeout.count()) + " ms";
  return ec.message();
}

tcp::resolver::results_type resolve(net::io_context& ioc, const Url& url) {
  tcp::resolver resolver(ioc);
  beast::error_code ec;
  // numeric hosts (the usual endpoints) resolve without a lookup
  auto results = resolver.resolve(url.host, url.port, ec);
  if (ec) throw HttpFailure("resolving " + url.host + ": " + ec.message());
  return results;
}

void connectAndSend(net::io_context& ioc, beast::tcp_stream& stream, const Url& url, const std::string& target,
                    const std::string& body, std::chrono::steady_clock::time_point deadline,
                    std::chrono::milliseconds timeout, bool keep_alive) {
  auto results = resolve(ioc, url);
  beast::error_code ec;
  bool done = false;
  stream.expires_at(deadline);
  stream.async_connect(results, [&](beast::error_code e, const tcp::endpoint&) {
    ec = e;
    done = true;
  });
  runUntil(ioc, done, deadline, stream);
  if (ec || !done) throw HttpFailure("connect: " + reason(ec ? ec : net::error::operation_aborted, timeout));

  http::request<http::string_body> req{http::verb::post, target, 11};
  req.set(http::field::host, url.host + ":" + url.port);
  req.set(http::field::content_type, "application/json");
  req.keep_alive(keep_alive);
  req.body() = body;
  req.prepare_payload();
  done = false;
  stream.expires_at(deadline);
  http::async_write(stream, req, [&](beast::error_code e, std::size_t) {
    ec = e;
    done = true;
  });
  runUntil(ioc, done, deadline, stream);
  if (ec || !done) throw HttpFailure("sending: " + reason(ec ? ec : net::error::operation_aborted, timeout));
}

}  // namespace

HttpAnswer httpPost(const Url& url, const std::string& target, const std::string& body,
                    std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  connectAndSend(ioc, stream, url, target, body, deadline, timeout, false);

  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(256u << 20);
  beast::error_code ec;
  bool done = false;
  stream.expires_at(deadline);
  http::async_read(stream, buffer, parser, [&](beast::error_code e, std::size_t) {
    ec = e;
    done = true;
  });
  runUntil(ioc, done, deadline, stream);
  if (ec || !done) throw HttpFailure("waiting for the answer: " + reason(ec ? ec : net::error::operation_aborted, timeout));
  beast::error_code ignored;
  stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
  return {parser.get().result_int(), std::move(parser.get().body())};
}

unsigned httpPostStream(const Url& url, const std::string& target, const std::string& body,
                        std::chrono::milliseconds connect_timeout, std::chrono::milliseconds poll,
                        const std::function<bool(const std::string&)>& on_bytes,
                        const std::function<bool()>& keep_going) {
  const auto deadline = std::chrono::steady_clock::now() + connect_timeout;
  net::io_context ioc;
  beast::tcp_stream stream(ioc);
  connectAndSend(ioc, stream, url, target, body, deadline, connect_timeout, true);

  beast::flat_buffer buffer;
  http::response_parser<http::empty_body> parser;
  parser.body_limit(boost::none);
  bool stop = false;
  std::string piece;
  auto on_chunk = [&](std::uint64_t, beast::string_view data, beast::error_code&) -> std::size_t {
    piece.assign(data.data(), data.size());
    if (!on_bytes(piece)) stop = true;
    return data.size();
  };
  parser.on_chunk_body(on_chunk);

  beast::error_code ec;
  bool done = false;
  stream.expires_at(deadline);
  http::async_read_header(stream, buffer, parser, [&](beast::error_code e, std::size_t) {
    ec = e;
    done = true;
  });
  runUntil(ioc, done, deadline, stream);
  if (ec || !done) throw HttpFailure("waiting for the answer: " + reason(ec ? ec : net::error::operation_aborted, connect_timeout));
  const unsigned status = parser.get().result_int();
  if (status != 200) return status;

  stream.expires_never();
  while (!stop && !parser.is_done()) {
    done = false;
    http::async_read_some(stream, buffer, parser, [&](beast::error_code e, std::size_t) {
      ec = e;
      done = true;
    });
    while (!done) {
      ioc.restart();
      ioc.run_for(poll);
      if (!done && !keep_going()) {
        beast::error_code ignored;
        stream.socket().close(ignored);
        ioc.restart();
        ioc.run();
        return status;
      }
    }
    if (ec) throw HttpFailure("stream: " + ec.message());
    if (!keep_going()) break;
  }
  beast::error_code ignored;
  stream.socket().close(ignored);
  return status;
}

}  // namespace groundsim::fleet
