// The bridge's LCM side: one receive thread, the server's channels decoded
// (with the reason for anything undecodable) and handed to callbacks that
// must not block (they only post work to the browser side). Publishing is
// thread-safe in LCM and happens from the caller's thread.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include <lcm/lcm-cpp.hpp>

#include <groundsim/asset_want_t.hpp>
#include <groundsim/car_state_t.hpp>
#include <groundsim/controls_t.hpp>
#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>
#include <groundsim/scenario_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/state_t.hpp>

#include "protocol/assets_client.hpp"
#include "protocol/channels.hpp"

namespace groundsim::web {

using net::kOpScenario;
using net::kScenarioChannel;

struct LcmHandlers {
  std::function<void(const groundsim::server_status_t&)> status;
  std::function<void(const groundsim::state_t&)> state;
  std::function<void(const groundsim::event_t&)> event;
  std::function<void(const groundsim::reply_t&)> reply;
  std::function<void(const groundsim::scenario_t&)> scenario;
  std::function<void(const std::string& channel, const std::string& reason)> bad;
  std::function<void(const groundsim::car_state_t&)> car_state;  // road cars (last: positional initializers)
  std::function<void(const groundsim::asset_want_t&)> asset_want;  // what a create of ours lacks
};

class LcmLink {
 public:
  LcmLink(const std::string& url, LcmHandlers handlers);
  ~LcmLink();
  bool good() const { return lcm_.good(); }
  void start();
  void stop();
  const std::string& clientId() const { return client_id_; }
  // The bus, for feeds that subscribe on their own (contact_feed.hpp) before start().
  lcm::LCM& bus() { return lcm_; }

  // Any thread. Fill client_id (and request_id for requests) before.
  void publish(const groundsim::request_t& r);
  void publish(const groundsim::drive_t& d);
  void publish(const groundsim::controls_t& c);
  // The parts of `assets` the wants ask for (net::sendWantedParts).
  void publishAssets(const std::vector<scenario::Asset>& assets, const std::vector<groundsim::asset_want_t>& wants);

 private:
  void onStatus(const lcm::ReceiveBuffer* b, const std::string& channel);
  void onState(const lcm::ReceiveBuffer* b, const std::string& channel);
  void onCarState(const lcm::ReceiveBuffer* b, const std::string& channel);
  void onEvent(const lcm::ReceiveBuffer* b, const std::string& channel);
  void onReply(const lcm::ReceiveBuffer* b, const std::string& channel);
  void onScenario(const lcm::ReceiveBuffer* b, const std::string& channel);
  void onAssetWant(const lcm::ReceiveBuffer* b, const std::string& channel);

  lcm::LCM lcm_;
  LcmHandlers h_;
  std::string client_id_;
  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace groundsim::web
