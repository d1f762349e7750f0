// The Foxglove port's listening socket (foxglove_server.hpp): it accepts
// connections and reads each one's HTTP upgrade request; a WebSocket upgrade
// offering one of our subprotocols is handed on with the subprotocol chosen,
// anything else is answered why not (426 or 400), counted and logged.
#pragma once

#include <functional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/http.hpp>

#include "bridge/foxglove_options.hpp"

namespace groundsim::web::foxglove {

class Listener {
 public:
  using Accepted = std::function<void(boost::asio::ip::tcp::socket,
                                      boost::beast::http::request<boost::beast::http::string_body>,
                                      std::string subprotocol)>;
  // opts and counters outlive the listener (the Server's).
  Listener(boost::asio::io_context& io, const Options& opts, Counters& counters, Accepted accepted);

  // Throws boost::system::system_error when the address cannot be bound;
  // the port bound (port 0: one the system chose).
  unsigned short listen(const std::string& address, unsigned short port);
  void close();

 private:
  void accept();
  void refused(const std::string& who, const std::string& why);

  boost::asio::ip::tcp::acceptor acceptor_;
  const Options& opts_;
  Counters& counters_;
  Accepted accepted_;
};

}  // namespace groundsim::web::foxglove
