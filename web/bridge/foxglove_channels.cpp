#include "bridge/foxglove_channels.hpp"

#include "protocol/channels.hpp"
#include "protocol/message_json.hpp"

namespace groundsim::web::foxglove {

namespace {

struct StreamInfo {
  const char* suffix;       // topic "/<session>" + suffix, as the recorder names it (client/record/recorder.cpp)
  const char* schema_name;  // the recorder's schema names
  const char* (*schema)();
};
const StreamInfo& info(Stream s) {
  static const StreamInfo kInfo[kStreams] = {
      {"/state", "groundsim.state", record::stateSchema},
      {"/car_state", "groundsim.car_state", record::carStateSchema},
      {"/contact", "groundsim.contact_state", record::contactStateSchema},
      {"/events", "groundsim.event", record::eventSchema},
      {"/applied", "groundsim.applied", record::appliedSchema},
      {"/events", "groundsim.event", record::eventSchema},
  };
  return kInfo[static_cast<int>(s)];
}

// What every session gets from its first heartbeat or message on.
constexpr Stream kAlways[] = {Stream::State, Stream::Events, Stream::Applied};

}  // namespace

std::string lcmChannel(const std::string& session, Stream s) {
  switch (s) {
    case Stream::State: return net::stateChannel(session);
    case Stream::CarState: return net::carStateChannel(session);
    case Stream::Contact: return net::contactChannel(session);
    case Stream::Applied: return net::appliedChannel(session);
    case Stream::Events:
    case Stream::AllEvents: return "";
  }
  return "";
}

ChannelRegistry::ChannelRegistry() {
  const std::uint64_t id = next_id_++;
  Channel& c = channels_[id];
  c.id = id;
  c.topic = info(Stream::AllEvents).suffix;
  c.schema_name = info(Stream::AllEvents).schema_name;
  c.schema = info(Stream::AllEvents).schema();
  c.metadata = {{"lcm_channel", net::kEventChannel}};
  streams_[id] = {"", Stream::AllEvents};
}

void ChannelRegistry::ensure(const std::string& session, Stream s, Clock::time_point now, Changes& out) {
  auto it = sessions_.find(session);
  if (it == sessions_.end()) {
    if (sessions_.size() >= kMaxSessions) return;
    it = sessions_.emplace(session, Session{}).first;
    for (Stream a : kAlways) ensure(session, a, now, out);
  }
  it->second.last = std::max(it->second.last, now);
  auto& slot = it->second.ids[static_cast<int>(s)];
  if (slot) return;
  const std::uint64_t id = next_id_++;
  slot = id;
  Channel& c = channels_[id];
  c.id = id;
  c.topic = "/" + session + info(s).suffix;
  c.schema_name = info(s).schema_name;
  c.schema = info(s).schema();
  c.metadata = {{"session", session}};
  const std::string lcm = lcmChannel(session, s);
  c.metadata["lcm_channel"] = lcm.empty() ? net::kEventChannel : lcm;
  streams_[id] = {session, s};
  out.added.push_back(&c);
}

ChannelRegistry::Changes ChannelRegistry::listed(const std::vector<std::string>& sessions, Clock::time_point now) {
  Changes out;
  for (const auto& id : sessions) ensure(id, Stream::State, now, out);
  return out;
}

ChannelRegistry::Changes ChannelRegistry::heard(const std::string& session, Stream s, Clock::time_point now) {
  Changes out;
  // an event may name a session that never existed (an error about an unknown id): events make no session
  if (s != Stream::AllEvents && s != Stream::Events) ensure(session, s, now, out);
  return out;
}

ChannelRegistry::Changes ChannelRegistry::expire(Clock::time_point now) {
  Changes out;
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    if (now - it->second.last <= kGoneAfter) {
      ++it;
      continue;
    }
    for (const auto& id : it->second.ids) {
      if (!id) continue;
      channels_.erase(*id);
      streams_.erase(*id);
      out.removed.push_back(*id);
    }
    it = sessions_.erase(it);
  }
  return out;
}

const Channel* ChannelRegistry::find(std::uint64_t id) const {
  const auto it = channels_.find(id);
  return it == channels_.end() ? nullptr : &it->second;
}

std::optional<std::uint64_t> ChannelRegistry::channelOf(const std::string& session, Stream s) const {
  if (s == Stream::AllEvents) return 1;  // made first, by the constructor
  const auto it = sessions_.find(session);
  if (it == sessions_.end()) return std::nullopt;
  return it->second.ids[static_cast<int>(s)];
}

std::optional<std::pair<std::string, Stream>> ChannelRegistry::streamOf(std::uint64_t id) const {
  const auto it = streams_.find(id);
  if (it == streams_.end()) return std::nullopt;
  return it->second;
}

std::vector<const Channel*> ChannelRegistry::all() const {
  std::vector<const Channel*> out;
  for (const auto& [id, c] : channels_) out.push_back(&c);
  return out;
}

}  // namespace groundsim::web::foxglove
