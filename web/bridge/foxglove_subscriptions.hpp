// The Foxglove endpoint's connected clients and what each subscribes to
// (foxglove_server.hpp): the protocol's subscribe and unsubscribe, checked
// entry by entry against the channel table (a bad entry gets a status error
// naming the field, the others still count, as the Foxglove SDK does);
// subscriptions that end with their channel; data routed to the clients
// subscribed; the LCM channels they want. I/O thread only.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include "bridge/foxglove_channels.hpp"
#include "bridge/foxglove_client.hpp"
#include "bridge/foxglove_options.hpp"

namespace groundsim::web::foxglove {

class Subscriptions {
 public:
  // registry and counters outlive this (the Server's).
  Subscriptions(const ChannelRegistry& registry, Counters& counters) : registry_(registry), counters_(counters) {}

  void add(Client* c);
  bool contains(Client* c) const { return clients_.count(c) != 0; }
  // Forgets c; true if it had subscriptions (the wanted channels change).
  bool remove(Client* c);

  // A text message of c's: subscribe or unsubscribe, or a status error; true
  // if its subscriptions changed. Nothing for a client not added.
  bool onText(Client* c, const std::string& text);
  // A status error to c, counted.
  void refuse(Client* c, const std::string& message);

  // Channels that go take their subscriptions with them (as the SDK does);
  // true if any ended.
  bool channelsGone(const std::vector<std::uint64_t>& removed);
  // A control message to every client.
  void broadcast(const std::shared_ptr<const std::string>& text);
  // A message of `channel` to the clients subscribed to it.
  void deliver(std::uint64_t channel, std::uint64_t ns, const std::shared_ptr<const std::string>& json);

  // The LCM channels of the channels subscribed to.
  std::unordered_set<std::string> wanted() const;
  std::size_t clients() const { return clients_.size(); }
  std::uint64_t count() const;

 private:
  struct ClientState {
    std::map<std::uint32_t, std::uint64_t> subs;        // subscription id -> channel
    std::map<std::uint64_t, std::uint32_t> by_channel;  // channel -> subscription id
  };
  bool subscribe(Client* c, ClientState& st, const Subscribe& sub);
  bool unsubscribe(Client* c, ClientState& st, const Unsubscribe& un);

  const ChannelRegistry& registry_;
  Counters& counters_;
  std::map<Client*, ClientState> clients_;
};

}  // namespace groundsim::web::foxglove
