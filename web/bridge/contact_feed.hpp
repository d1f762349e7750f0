// The contact channels (GROUNDSIM_CONTACT_<session id>: contact_state_t,
// the objects with mass and the hits under way, published right after each
// state_t of a scene with contact between bodies) re-encoded as JSON for
// the browsers watching that session. Its own subscription on the bridge's
// LCM, beside the hub: the LCM thread decodes (counting and dropping what
// does not decode, like every other channel), skips sessions nobody
// watches, and hands the JSON to `deliver`, which only posts it on.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <lcm/lcm-cpp.hpp>

namespace groundsim::web {

class ContactFeed {
 public:
  struct Hooks {
    std::function<bool(const std::string& session)> watched;  // any thread
    // LCM thread: must not block (the bridge posts to the I/O thread)
    std::function<void(const std::string& session, std::shared_ptr<const std::string> json)> deliver;
    std::function<void(const std::string& channel, const std::string& reason)> bad;  // undecodable
  };

  // Subscribes to every session's contact channel; nullptr: no subscription
  // (tests feed datagrams to handle()).
  ContactFeed(lcm::LCM* lcm, Hooks hooks);
  ~ContactFeed();
  ContactFeed(const ContactFeed&) = delete;
  ContactFeed& operator=(const ContactFeed&) = delete;

  // One datagram of `channel`. Never throws.
  void handle(const void* data, int size, const std::string& channel) noexcept;

  std::uint64_t undecodable() const { return undecodable_; }
  std::uint64_t forwarded() const { return forwarded_; }

 private:
  void onMessage(const lcm::ReceiveBuffer* b, const std::string& channel);

  lcm::LCM* lcm_;
  lcm::Subscription* sub_ = nullptr;
  Hooks hooks_;
  std::atomic<std::uint64_t> undecodable_{0}, forwarded_{0};
};

}  // namespace groundsim::web
