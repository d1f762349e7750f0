#include "bridge/contact_feed.hpp"

#include <groundsim/contact_state_t.hpp>

#include "bridge/state_json.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"

namespace groundsim::web {

ContactFeed::ContactFeed(lcm::LCM* lcm, Hooks hooks) : lcm_(lcm), hooks_(std::move(hooks)) {
  if (!lcm_ || !lcm_->good()) return;
  // one subscription for every session, as for states: the queue holds a burst of many sessions' frames
  sub_ = lcm_->subscribe(std::string(net::kContactPrefix) + ".*", &ContactFeed::onMessage, this);
  if (sub_) sub_->setQueueCapacity(4096);
}

ContactFeed::~ContactFeed() {
  if (lcm_ && sub_) lcm_->unsubscribe(sub_);
}

void ContactFeed::onMessage(const lcm::ReceiveBuffer* b, const std::string& channel) {
  handle(b->data, static_cast<int>(b->data_size), channel);
}

void ContactFeed::handle(const void* data, int size, const std::string& channel) noexcept {
  try {
    groundsim::contact_state_t m;
    const net::DecodeResult d = net::decodeMessage(data, size, m, "groundsim.contact_state_t");
    if (!d.ok()) {
      ++undecodable_;
      if (hooks_.bad) hooks_.bad(channel, d.reason);
      return;
    }
    if (hooks_.watched && !hooks_.watched(m.session_id)) return;
    auto json = std::make_shared<const std::string>(contactJson(m));
    ++forwarded_;
    if (hooks_.deliver) hooks_.deliver(m.session_id, std::move(json));
  } catch (...) {
    // out of memory while re-encoding: this frame is lost, the next one comes
    ++undecodable_;
  }
}

}  // namespace groundsim::web
