#include "bridge/requests.hpp"

#include <chrono>

namespace groundsim::web {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

Requests::Requests(asio::io_context& io, Publish publish, std::string client_id, double timeout_s)
    : io_(io), publish_(std::move(publish)), client_id_(std::move(client_id)), timeout_s_(timeout_s) {}

void Requests::stamp(groundsim::request_t& r) {
  if (r.client_id.empty()) r.client_id = client_id_;  // a browser's create names that browser
  r.request_id = next_++;
  r.utime = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
}

void Requests::send(groundsim::request_t r, Done done) {
  stamp(r);
  auto timer = std::make_shared<asio::steady_timer>(io_);
  timer->expires_after(std::chrono::milliseconds(static_cast<int>(timeout_s_ * 1000)));
  const std::int64_t id = r.request_id;
  timer->async_wait([this, id](const boost::system::error_code& ec) {
    if (ec) return;
    auto it = pending_.find(id);
    if (it == pending_.end()) return;
    auto done = std::move(it->second.done);
    pending_.erase(it);
    if (done) done(nullptr);
  });
  pending_[id] = Pending{std::move(done), timer};
  publish_(r);
}

void Requests::sendUnanswered(groundsim::request_t r) {
  stamp(r);
  publish_(r);
}

void Requests::onReply(const groundsim::reply_t& r) {
  auto it = pending_.find(r.request_id);
  if (it == pending_.end()) return;
  auto done = std::move(it->second.done);
  it->second.timer->cancel();
  pending_.erase(it);
  if (done) done(&r);
}

bool Requests::ours(const std::string& id) const {
  const std::string& me = client_id_;
  return id == me || (id.size() > me.size() + 2 && id.compare(0, me.size(), me) == 0 && id.compare(me.size(), 2, "-b") == 0);
}

std::string Requests::browserClientId(std::uint64_t serial) const { return client_id_ + "-b" + std::to_string(serial); }

groundsim::request_t Requests::stop(const std::string& session, const std::string& token) {
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_STOP;
  r.session_id = session;
  r.token = token;
  return r;
}

}  // namespace groundsim::web
