// HTTP and WebSocket on Boost.Beast: GET serves the bundled page (files read
// into memory at start, so no path from a browser ever reaches the file
// system), GET /ws upgrades to the WebSocket the page talks on, GET /metrics
// (Prometheus text format, docs/metrics.md) and GET /health answer from the
// hub's and the sockets' counters, GET /recordings... reads recordings
// (recordings.hpp) on a thread of its own, at most four at a time. One I/O
// thread runs every socket; nothing here blocks it.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "bridge/hub.hpp"
#include "bridge/recordings.hpp"

namespace groundsim::web {

struct StaticFile {
  std::string content_type;
  std::string body;
};
// What browsers were sent since start, counted by their sockets (I/O thread only).
struct WebTraffic {
  std::uint64_t states_forwarded = 0;  // state messages written to a browser's socket
  std::uint64_t states_skipped = 0;    // replaced in a browser's newest-only slot before being written
  std::uint64_t bytes_sent = 0;        // WebSocket message payloads and whole HTTP responses
};
// The bridge's GET /metrics text and GET /health JSON (I/O thread).
std::string bridgeMetrics(const Hub& hub, const WebTraffic& traffic);
std::string bridgeHealth(const Hub& hub);

// Reads every file of `dir` (not recursively): URL path "/" + name, and "/"
// for index.html.
std::map<std::string, StaticFile> loadStaticFiles(const std::string& dir);

class WebServer {
 public:
  // recordings_dir: MCAP files served at /recordings; configs_dir: where a
  // recording's scene finds the files its scenario names that the file does
  // not hold (recordings.hpp)
  WebServer(boost::asio::io_context& io, Hub& hub, std::map<std::string, StaticFile> files,
            std::string recordings_dir = "", std::string configs_dir = "");
  // Throws boost::system::system_error when the address cannot be bound.
  void listen(const std::string& address, unsigned short port);
  unsigned short port() const { return port_; }
  // More lines for GET /metrics (I/O thread): the Foxglove endpoint's (foxglove_server.hpp).
  void addMetrics(std::function<std::string()> more) { *more_metrics_ = std::move(more); }

 private:
  void accept();

  boost::asio::io_context& io_;
  Hub& hub_;
  std::shared_ptr<const std::map<std::string, StaticFile>> files_;
  std::shared_ptr<WebTraffic> traffic_;
  std::shared_ptr<const Recordings> recordings_;
  std::shared_ptr<std::function<std::string()>> more_metrics_ = std::make_shared<std::function<std::string()>>();
  boost::asio::ip::tcp::acceptor acceptor_;
  unsigned short port_ = 0;
};

}  // namespace groundsim::web
