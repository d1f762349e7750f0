// One Foxglove WebSocket connection (foxglove_server.hpp): it reads the
// client's messages piece by piece and hands them to its owner, and writes
// its outbox: the protocol's control messages in order, never dropped (a
// client that leaves max_control of them unread is closed), and its data
// messages in a bounded queue where the oldest goes when a new one comes
// (told by a status warning at most every 5 s). I/O thread only.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "bridge/foxglove_options.hpp"
#include "bridge/foxglove_protocol.hpp"

namespace groundsim::web::foxglove {

// "address:port" of a connected socket ("?" when it has none).
std::string peerName(const boost::asio::ip::tcp::socket& s);

class Client : public std::enable_shared_from_this<Client> {
 public:
  // Who keeps the connected clients (the Server): told on the I/O thread.
  class Owner {
   public:
    virtual void attach(Client* c) = 0;                             // the handshake is done
    virtual void detach(Client* c) = 0;                             // closed: forget it
    virtual void onText(Client* c, const std::string& text) = 0;    // a text message of at most max_message_bytes
    virtual void refuse(Client* c, const std::string& message) = 0;  // a message it cannot take

   protected:
    ~Owner() = default;
  };

  // opts, counters and owner outlive the client (the Server's).
  Client(boost::asio::ip::tcp::socket socket, std::string subprotocol, const Options& opts, Counters& counters,
         Owner& owner);

  // Answers the upgrade request; once open, the owner's attach() hears of it.
  void start(boost::beast::http::request<boost::beast::http::string_body> req);

  const std::string& name() const { return name_; }
  const std::string& subprotocol() const { return subprotocol_; }

  // In order, never dropped; a client that leaves max_control of them unread is closed.
  void sendControl(std::shared_ptr<const std::string> text);
  // Bounded: the oldest data message goes when the outbox is full.
  void sendData(std::uint32_t subscription, std::uint64_t ns, std::shared_ptr<const std::string> json);
  // Drops what waits for a subscription that ends (its id may be reused).
  void forget(std::uint32_t subscription);
  // The bridge closes this client (I/O thread; from outside its own handlers only).
  void close();
  void markAttached() { attached_ = true; }

 private:
  struct Data {
    std::array<std::uint8_t, kDataHeaderBytes> header;
    std::shared_ptr<const std::string> payload;
    std::uint32_t subscription;
  };
  using Clock = std::chrono::steady_clock;

  void read();
  void onRead(boost::beast::error_code ec, std::size_t n);
  void onMessageDone();
  void tooBig();
  void write();
  void warnOfDrops();

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  const Options& opts_;
  Counters& counters_;
  Owner& owner_;
  std::string subprotocol_, name_;
  boost::beast::flat_buffer buffer_;
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

}  // namespace groundsim::web::foxglove
