// The bridge's requests to the server and their replies: each request gets
// the next id and the time, and its `done` is called once, with the reply or
// with nullptr when none came within the timeout. Replies arrive on the I/O
// thread (Hub posts them there).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>

namespace groundsim::web {

class Requests {
 public:
  using Done = std::function<void(const groundsim::reply_t*)>;
  using Publish = std::function<void(const groundsim::request_t&)>;

  Requests(boost::asio::io_context& io, Publish publish, std::string client_id, double timeout_s);

  // Sends `r` (from the bridge unless it names a client of its own).
  void send(groundsim::request_t r, Done done);
  // Sends `r` with no reply awaited: at shutdown, when the I/O loop that
  // would time it out is ending.
  void sendUnanswered(groundsim::request_t r);
  void onReply(const groundsim::reply_t& r);

  // Whether a message on the bus is for this bridge: its id, or one of its
  // browsers' (id-bN, protocol/client_id.hpp).
  bool ours(const std::string& client_id) const;
  const std::string& clientId() const { return client_id_; }
  // this bridge's principal for browser `serial`'s creates
  std::string browserClientId(std::uint64_t serial) const;

  static groundsim::request_t stop(const std::string& session, const std::string& token);

 private:
  void stamp(groundsim::request_t& r);

  struct Pending {
    Done done;
    std::shared_ptr<boost::asio::steady_timer> timer;
  };
  boost::asio::io_context& io_;
  Publish publish_;
  std::string client_id_;
  double timeout_s_;
  std::int64_t next_ = 1;
  std::map<std::int64_t, Pending> pending_;
};

}  // namespace groundsim::web
