#include "bridge/foxglove_subscriptions.hpp"

#include <variant>

namespace groundsim::web::foxglove {

void Subscriptions::add(Client* c) { clients_[c] = ClientState{}; }

bool Subscriptions::remove(Client* c) {
  const auto it = clients_.find(c);
  if (it == clients_.end()) return false;
  const bool had = !it->second.subs.empty();
  clients_.erase(it);
  return had;
}

void Subscriptions::refuse(Client* c, const std::string& message) {
  ++counters_.client_errors;
  c->sendControl(std::make_shared<const std::string>(status(Level::Error, message)));
}

bool Subscriptions::onText(Client* c, const std::string& text) {
  const auto it = clients_.find(c);
  if (it == clients_.end()) return false;
  ClientState& st = it->second;
  const ClientMessage m = parseClientMessage(text);
  if (const auto* e = std::get_if<ClientError>(&m)) {
    refuse(c, e->text());
    return false;
  }
  if (const auto* sub = std::get_if<Subscribe>(&m)) return subscribe(c, st, *sub);
  if (const auto* un = std::get_if<Unsubscribe>(&m)) return unsubscribe(c, st, *un);
  return false;
}

// each entry on its own: a bad one is refused, the others still count (as the SDK does)
bool Subscriptions::subscribe(Client* c, ClientState& st, const Subscribe& sub) {
  bool changed = false;
  for (std::size_t i = 0; i < sub.subscriptions.size(); ++i) {
    const Subscription& s = sub.subscriptions[i];
    const std::string at = "/subscriptions/" + std::to_string(i);
    if (!registry_.find(s.channel)) {
      refuse(c, "refused " + at + "/channelId: unknown channel " + std::to_string(s.channel));
    } else if (st.subs.count(s.id)) {
      refuse(c, "refused " + at + "/id: subscription " + std::to_string(s.id) + " is in use (channel " +
                    std::to_string(st.subs[s.id]) + ")");
    } else if (const auto b = st.by_channel.find(s.channel); b != st.by_channel.end()) {
      refuse(c, "refused " + at + "/channelId: channel " + std::to_string(s.channel) +
                    " is already subscribed (subscription " + std::to_string(b->second) + ")");
    } else {
      st.subs[s.id] = s.channel;
      st.by_channel[s.channel] = s.id;
      changed = true;
    }
  }
  return changed;
}

bool Subscriptions::unsubscribe(Client* c, ClientState& st, const Unsubscribe& un) {
  bool changed = false;
  for (std::size_t i = 0; i < un.ids.size(); ++i) {
    const auto s = st.subs.find(un.ids[i]);
    if (s == st.subs.end()) {
      refuse(c, "refused /subscriptionIds/" + std::to_string(i) + ": unknown subscription " +
                    std::to_string(un.ids[i]));
      continue;
    }
    c->forget(s->first);
    st.by_channel.erase(s->second);
    st.subs.erase(s);
    changed = true;
  }
  return changed;
}

bool Subscriptions::channelsGone(const std::vector<std::uint64_t>& removed) {
  bool ended = false;
  for (auto& [c, st] : clients_)
    for (const std::uint64_t id : removed) {
      const auto it = st.by_channel.find(id);
      if (it == st.by_channel.end()) continue;
      c->forget(it->second);
      st.subs.erase(it->second);
      st.by_channel.erase(it);
      ended = true;
    }
  return ended;
}

void Subscriptions::broadcast(const std::shared_ptr<const std::string>& text) {
  for (auto& [c, st] : clients_) c->sendControl(text);
}

void Subscriptions::deliver(std::uint64_t channel, std::uint64_t ns, const std::shared_ptr<const std::string>& json) {
  for (auto& [c, st] : clients_) {
    const auto it = st.by_channel.find(channel);
    if (it != st.by_channel.end()) c->sendData(it->second, ns, json);
  }
}

std::unordered_set<std::string> Subscriptions::wanted() const {
  std::unordered_set<std::string> wanted;
  for (const auto& [c, st] : clients_)
    for (const auto& [channel, sub] : st.by_channel)
      if (const auto s = registry_.streamOf(channel)) {
        const std::string lcm = lcmChannel(s->first, s->second);
        if (!lcm.empty()) wanted.insert(lcm);
      }
  return wanted;
}

std::uint64_t Subscriptions::count() const {
  std::uint64_t subscriptions = 0;
  for (const auto& [c, st] : clients_) subscriptions += st.subs.size();
  return subscriptions;
}

}  // namespace groundsim::web::foxglove
