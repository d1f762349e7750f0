#include "bridge/foxglove_feed.hpp"

#include <cstring>

#include <groundsim/applied_t.hpp>
#include <groundsim/car_state_t.hpp>
#include <groundsim/contact_state_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/state_t.hpp>

#include "bridge/browser_message.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/message_json.hpp"

namespace groundsim::web::foxglove {

namespace {

std::uint64_t nowNs() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// The per-session streams, by their channel's prefix.
struct Prefixed {
  const char* prefix;
  Stream stream;
};
constexpr Prefixed kPrefixed[] = {{net::kStatePrefix, Stream::State},
                                  {net::kCarStatePrefix, Stream::CarState},
                                  {net::kContactPrefix, Stream::Contact},
                                  {net::kAppliedPrefix, Stream::Applied}};

// A heard channel's last `heard` is forgotten after this (and the map is
// swept when it grows), so sessions that come and go do not pile up.
constexpr auto kHeardEvery = std::chrono::seconds(1);
constexpr std::size_t kHeardSweepAt = 4096;

template <class T>
bool decode(const void* data, int size, const std::string& channel, const char* type, T& out,
            const Feed::Hooks& h) {
  const net::DecodeResult d = net::decodeMessage(data, size, out, type);
  if (!d.ok() && h.bad) h.bad(channel, d.reason);
  return d.ok();
}

}  // namespace

Feed::Feed(lcm::LCM* lcm, Hooks hooks)
    : lcm_(lcm), hooks_(std::move(hooks)), wanted_(std::make_shared<const std::unordered_set<std::string>>()) {
  if (!lcm_ || !lcm_->good()) return;
  auto sub = [&](const std::string& pattern, int queue) {
    if (auto* s = lcm_->subscribe(pattern, &Feed::onMessage, this)) {
      s->setQueueCapacity(queue);
      subs_.push_back(s);
    }
  };
  // every session's streams share one subscription each: deep queues for bursts, as LcmLink's
  for (const auto& p : kPrefixed) sub(std::string(p.prefix) + ".*", 4096);
  sub(net::kEventChannel, 1024);
  sub(net::kStatusChannel, 64);
}

Feed::~Feed() {
  if (lcm_)
    for (auto* s : subs_) lcm_->unsubscribe(s);
}

void Feed::setWanted(std::unordered_set<std::string> lcm_channels) {
  auto next = std::make_shared<const std::unordered_set<std::string>>(std::move(lcm_channels));
  std::lock_guard<std::mutex> lk(mu_);
  wanted_ = std::move(next);
}

bool Feed::wanted(const std::string& channel) {
  std::shared_ptr<const std::unordered_set<std::string>> w;
  {
    std::lock_guard<std::mutex> lk(mu_);
    w = wanted_;
  }
  return w->count(channel) > 0;
}

void Feed::noteHeard(const std::string& channel, const std::string& session, Stream s) {
  const auto now = std::chrono::steady_clock::now();
  auto it = heard_at_.find(channel);
  if (it != heard_at_.end() && now - it->second < kHeardEvery) return;
  if (it == heard_at_.end()) {
    if (heard_at_.size() >= kHeardSweepAt)
      for (auto j = heard_at_.begin(); j != heard_at_.end();)
        j = now - j->second > 10 * kHeardEvery ? heard_at_.erase(j) : std::next(j);
    it = heard_at_.emplace(channel, now).first;
  }
  it->second = now;
  if (hooks_.heard) hooks_.heard(session, s);
}

void Feed::onMessage(const lcm::ReceiveBuffer* b, const std::string& channel) {
  handle(b->data, static_cast<int>(b->data_size), channel);
}

void Feed::handle(const void* data, int size, const std::string& channel) noexcept {
  try {
    const std::uint64_t ns = nowNs();
    if (channel == net::kStatusChannel) {
      groundsim::server_status_t m;
      if (!decode(data, size, channel, "groundsim.server_status_t", m, hooks_)) return;
      std::vector<std::string> ids;
      for (const auto& s : m.sessions)
        if (validSessionId(s.session_id)) ids.push_back(s.session_id);
      if (hooks_.listed) hooks_.listed(std::move(ids));
      return;
    }
    if (channel == net::kEventChannel) {
      groundsim::event_t m;
      if (!decode(data, size, channel, "groundsim.event_t", m, hooks_)) return;
      ++decoded_;
      auto json = std::make_shared<const std::string>(record::toJson(m));
      const std::string session = validSessionId(m.session_id) ? m.session_id : "";
      if (hooks_.message) hooks_.message(session, Stream::Events, ns, std::move(json));
      return;
    }
    for (const auto& p : kPrefixed) {
      if (!startsWith(channel, p.prefix)) continue;
      const std::string session = channel.substr(std::strlen(p.prefix));
      if (!validSessionId(session)) return;  // not a session's channel: no topic is made of it
      noteHeard(channel, session, p.stream);
      if (!wanted(channel)) return;
      std::string json;
      switch (p.stream) {
        case Stream::State: {
          groundsim::state_t m;
          if (!decode(data, size, channel, "groundsim.state_t", m, hooks_)) return;
          json = record::toJson(m);
          break;
        }
        case Stream::CarState: {
          groundsim::car_state_t m;
          if (!decode(data, size, channel, "groundsim.car_state_t", m, hooks_)) return;
          json = record::toJson(m);
          break;
        }
        case Stream::Contact: {
          groundsim::contact_state_t m;
          if (!decode(data, size, channel, "groundsim.contact_state_t", m, hooks_)) return;
          json = record::toJson(m);
          break;
        }
        case Stream::Applied: {
          groundsim::applied_t m;
          if (!decode(data, size, channel, "groundsim.applied_t", m, hooks_)) return;
          json = record::toJson(m);
          break;
        }
        default: return;
      }
      ++decoded_;
      if (hooks_.message) hooks_.message(session, p.stream, ns, std::make_shared<const std::string>(std::move(json)));
      return;
    }
  } catch (...) {
    // out of memory while converting: this message is lost to Foxglove clients, the next one comes
  }
}

}  // namespace groundsim::web::foxglove
