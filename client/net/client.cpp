#include "client.hpp"

#include <chrono>
#include <algorithm>
#include <random>

#include <unistd.h>

#include "protocol/client_id.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/text.hpp"

namespace groundsim::cli {

std::int64_t wallMicros() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

NetClient::NetClient(const std::string& url, bool deep_receive)
    : url_(deep_receive ? net::withReceiveBuffer(url) : (url.empty() ? net::defaultUrl() : url)),
      lcm_(url_),
      watch_(lcm_) {
  if (!lcm_.good())
    throw NetError("cannot open LCM URL " + net::quoted(url_) + " (no multicast route? e.g. `ip route add 224.0.0.0/4 dev lo`)");
  client_id_ = net::newClientId("cli");  // principal/instance (protocol/client_id.hpp)
  wants_.setClientId(client_id_);
  // replies and events of every client share one channel: keep ours only
  lcm_.subscribe(net::kReplyChannel, &NetClient::onReply, this)->setQueueCapacity(net::kDeepQueue);
  lcm_.subscribe(net::kEventChannel, &NetClient::onEvent, this)->setQueueCapacity(net::kDeepQueue);
  lcm_.subscribe(net::kAssetWantChannel, &NetClient::onAssetWant, this)->setQueueCapacity(net::kDeepQueue);
}

void NetClient::onAssetWant(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  wants_.addDatagram(rbuf->data, static_cast<int>(rbuf->data_size));
}

groundsim::reply_t NetClient::create(const groundsim::request_t& req, const std::vector<scenario::Asset>& assets,
                                     double timeout_s) {
  groundsim::reply_t r;
  for (int round = 0; round < net::kAssetRounds; ++round) {
    r = call(req, timeout_s);
    // a part the server refused (hash, size) is reported before this reply
    for (const groundsim::event_t& e : takeEvents())
      if (e.channel == net::kAssetChannel) {
        r.ok = false;
        r.error_code = groundsim::event_t::ERR_BAD_REQUEST;
        r.error = e.reason;
        return r;
      }
    if (r.ok || r.error_code != groundsim::asset_want_t::ERR_MISSING_ASSETS || assets.empty()) return r;
    try {
      net::sendWantedParts(lcm_, client_id_, assets, wants_.take(r.request_id));
    } catch (const std::exception& e) {
      throw NetError(std::string("sending the scenario's files: ") + e.what());
    }
  }
  r.error += " (still missing after " + std::to_string(net::kAssetRounds) + " rounds of sending)";
  return r;
}

void NetClient::onReply(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::reply_t m;
  if (!net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.reply_t").ok()) return;
  if (m.client_id == client_id_ && m.request_id == waiting_for_) reply_ = std::move(m);
}

void NetClient::onEvent(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::event_t m;
  if (!net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.event_t").ok()) return;
  if (m.client_id == client_id_ && m.severity == groundsim::event_t::SEVERITY_ERROR) events_.push_back(std::move(m));
}

groundsim::reply_t NetClient::call(groundsim::request_t req, double timeout_s) {
  req.utime = wallMicros();
  req.seq = seq_++;
  req.request_id = seq_;  // > 0: 0 marks "no request" in events
  req.client_id = client_id_;
  waiting_for_ = req.request_id;
  reply_.reset();
  if (lcm_.publish(net::kRequestChannel, &req) != 0) throw NetError("cannot publish on " + url_);
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + std::chrono::duration<double>(std::min(timeout_s, 1e9));
  // a list changes nothing, so a datagram lost on the way (a request, or
  // its reply: a snooping switch that has not yet learnt this new process's
  // group membership drops it) is worth asking again, with the same id
  const bool idempotent = req.op == groundsim::request_t::OP_LIST;
  auto next_ask = start + kAskAgain;
  while (!reply_) {
    if (idempotent && std::chrono::steady_clock::now() >= next_ask) {
      if (lcm_.publish(net::kRequestChannel, &req) != 0) throw NetError("cannot publish on " + url_);
      next_ask += kAskAgain;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0)
      throw NetError("no reply from groundsim-server within " + net::number(timeout_s) + " s on " + url_ +
                     (watch_.heartbeats() > 0 ? " (its heartbeat is there: the server is busy or dropped the request)"
                                              : " (is the server running with the same --lcm-url?)"));
    pump(static_cast<int>(std::min<long long>(left.count() + 1, idempotent ? 100 : 200)));
  }
  waiting_for_ = -1;
  groundsim::reply_t r = std::move(*reply_);
  reply_.reset();
  return r;
}

void NetClient::pump(int ms) {
  if (watch_.lost()) throw NetError(watch_.lostMessage(url_));
  lcm_.handleTimeout(ms);
}

void NetClient::send(groundsim::drive_t cmd) {
  cmd.utime = wallMicros();
  cmd.seq = seq_++;
  cmd.client_id = client_id_;
  if (lcm_.publish(net::kDriveChannel, &cmd) != 0) throw NetError("cannot publish on " + url_);
}

void NetClient::send(groundsim::controls_t cmd) {
  cmd.utime = wallMicros();
  cmd.seq = seq_++;
  cmd.client_id = client_id_;
  if (lcm_.publish(net::kControlsChannel, &cmd) != 0) throw NetError("cannot publish on " + url_);
}

std::vector<groundsim::event_t> NetClient::takeEvents() {
  std::vector<groundsim::event_t> out;
  out.swap(events_);
  return out;
}

}  // namespace groundsim::cli
