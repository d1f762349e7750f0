#include "bridge/lcm_link.hpp"

#include <unistd.h>

#include <random>

#include "protocol/channels.hpp"
#include "protocol/codec.hpp"

namespace groundsim::web {

using namespace groundsim::net;

LcmLink::LcmLink(const std::string& url, LcmHandlers handlers)
    : lcm_(withReceiveBuffer(url)), h_(std::move(handlers)) {
  std::random_device rd;
  client_id_ = "web-" + std::to_string(::getpid()) + "-" + std::to_string(rd() % 100000);
  if (!lcm_.good()) return;
  // queues deep enough for bursts: states of every session on the bus share one subscription
  lcm_.subscribe(kStatusChannel, &LcmLink::onStatus, this)->setQueueCapacity(64);
  lcm_.subscribe(std::string(kStatePrefix) + ".*", &LcmLink::onState, this)->setQueueCapacity(4096);
  lcm_.subscribe(std::string(kCarStatePrefix) + ".*", &LcmLink::onCarState, this)->setQueueCapacity(4096);
  lcm_.subscribe(kEventChannel, &LcmLink::onEvent, this)->setQueueCapacity(1024);
  lcm_.subscribe(kReplyChannel, &LcmLink::onReply, this)->setQueueCapacity(1024);
  lcm_.subscribe(kScenarioChannel, &LcmLink::onScenario, this)->setQueueCapacity(64);
  lcm_.subscribe(kAssetWantChannel, &LcmLink::onAssetWant, this)->setQueueCapacity(1024);
}

LcmLink::~LcmLink() { stop(); }

void LcmLink::start() {
  running_ = true;
  thread_ = std::thread([this] {
    while (running_) lcm_.handleTimeout(50);
  });
}

void LcmLink::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void LcmLink::publish(const groundsim::request_t& r) { lcm_.publish(kRequestChannel, &r); }
void LcmLink::publish(const groundsim::drive_t& d) { lcm_.publish(kDriveChannel, &d); }
void LcmLink::publish(const groundsim::controls_t& c) { lcm_.publish(kControlsChannel, &c); }
void LcmLink::publishAssets(const std::vector<scenario::Asset>& assets,
                            const std::vector<groundsim::asset_want_t>& wants) {
  sendWantedParts(lcm_, client_id_, assets, wants);
}

namespace {
template <class T, class F>
void dispatch(const lcm::ReceiveBuffer* b, const std::string& channel, const char* type, const F& handler,
              const LcmHandlers& h) {
  T msg;
  const DecodeResult d = decodeMessage(b->data, static_cast<int>(b->data_size), msg, type);
  if (!d.ok()) {
    if (h.bad) h.bad(channel, d.reason);
    return;
  }
  if (handler) handler(msg);
}
}  // namespace

void LcmLink::onStatus(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::server_status_t>(b, c, "groundsim.server_status_t", h_.status, h_);
}
void LcmLink::onState(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::state_t>(b, c, "groundsim.state_t", h_.state, h_);
}
void LcmLink::onCarState(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::car_state_t>(b, c, "groundsim.car_state_t", h_.car_state, h_);
}
void LcmLink::onEvent(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::event_t>(b, c, "groundsim.event_t", h_.event, h_);
}
void LcmLink::onReply(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::reply_t>(b, c, "groundsim.reply_t", h_.reply, h_);
}
void LcmLink::onScenario(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::scenario_t>(b, c, "groundsim.scenario_t", h_.scenario, h_);
}
void LcmLink::onAssetWant(const lcm::ReceiveBuffer* b, const std::string& c) {
  dispatch<groundsim::asset_want_t>(b, c, "groundsim.asset_want_t", h_.asset_want, h_);
}

}  // namespace groundsim::web
