// Opens a TCP acceptor on address:port (port 0: one the kernel picks) and
// returns the port it listens on: the page's server and the Foxglove
// endpoint listen the same way.
#pragma once

#include <string>

#include <boost/asio/ip/tcp.hpp>

namespace groundsim::web {

inline unsigned short listenOn(boost::asio::ip::tcp::acceptor& acceptor, const std::string& address,
                               unsigned short port) {
  const boost::asio::ip::tcp::endpoint ep(boost::asio::ip::make_address(address), port);
  acceptor.open(ep.protocol());
  acceptor.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor.bind(ep);
  acceptor.listen();
  return acceptor.local_endpoint().port();
}

}  // namespace groundsim::web
