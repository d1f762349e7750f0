#include "bridge/recording_reads.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <set>
#include <vector>

#include "bridge/state_json.hpp"
#include "recording/mcap_reader.hpp"

namespace groundsim::web {
namespace {

constexpr int kDefaultStates = 1000;
constexpr int kMaxStates = 5000;
constexpr std::size_t kMaxBody = 16u << 20;
constexpr int kMaxEvents = 5000;

std::uint64_t ns(double s) { return static_cast<std::uint64_t>(std::llround(s * 1e9)); }

// What a states request asks for.
struct StatesAsk {
  std::optional<double> at, from, to;
  int max = kDefaultStates;
  bool with_contacts = false;
};

// The request's parameters; why not (a 400's reason) if they do not do.
std::string readAsk(const Query& q, StatesAsk& ask) {
  std::string why;
  ask.at = seconds(q, "at", why);
  ask.from = seconds(q, "from", why);
  ask.to = seconds(q, "to", why);
  if (!why.empty()) return why;
  if (!ask.at && !(ask.from && ask.to)) return "give at=T, or from=T0 and to=T1 (s of simulation time)";
  if (ask.from && ask.to && *ask.to < *ask.from) return "to: must be >= from";
  if (auto m = q.find("max"); m != q.end()) {
    char* end = nullptr;
    const long v = std::strtol(m->second.c_str(), &end, 10);
    if (m->second.empty() || *end || v < 1 || v > kMaxStates)
      return "max: must be an integer in [1, " + std::to_string(kMaxStates) + "], got " + web::quoted(m->second.substr(0, 40));
    ask.max = static_cast<int>(v);
  }
  if (auto c = q.find("contacts"); c != q.end()) {
    if (c->second != "0" && c->second != "1") return "contacts: must be 0 or 1, got " + web::quoted(c->second.substr(0, 40));
    ask.with_contacts = c->second == "1";
  }
  return "";
}

// The messages read, as they go into the answer.
struct Window {
  std::vector<std::string> states, contacts;
  bool more = false;
};

// The newest state at or before T: the second before it holds one at any
// publish rate above 1 Hz; else the whole span before T.
void readInstant(recording::McapReader& r, std::uint16_t channel, double at, Window& w) {
  std::string last;
  const std::uint64_t t = ns(at);
  for (std::uint64_t back : {std::uint64_t{1'000'000'000}, t}) {
    r.readMessages([&](const recording::McapMessage& m) { last = m.data; }, {channel}, t > back ? t - back : 0, t);
    if (!last.empty()) break;
  }
  if (!last.empty()) w.states.push_back(std::move(last));
}

// States and (contacts=1) the contact states beside them (objects with
// mass, hits), in one pass; a window cut at `max` states is cut for both at
// the last state's time.
void readWindow(recording::McapReader& r, std::uint16_t channel, std::optional<std::uint16_t> contact_channel,
                const StatesAsk& ask, Window& w) {
  std::set<std::uint16_t> wanted{channel};
  if (ask.with_contacts && contact_channel) wanted.insert(*contact_channel);
  std::size_t bytes = 0;
  std::uint64_t cut_at = 0;
  r.readMessages(
      [&](const recording::McapMessage& m) {
        if (w.more && m.log_time > cut_at) return;
        const bool state = m.channel == channel;
        if (bytes + m.data.size() > kMaxBody || (state && static_cast<int>(w.states.size()) >= ask.max)) {
          if (!w.more) cut_at = m.log_time > 0 ? m.log_time - 1 : 0;
          w.more = true;
          return;
        }
        bytes += m.data.size();
        (state ? w.states : w.contacts).push_back(m.data);
      },
      wanted, ns(*ask.from), ns(*ask.to));
}

std::string windowJson(const std::string& session, const Window& w, bool with_contacts) {
  std::string out = "{\"session\":" + web::quoted(session) + ",\"states\":[";
  for (std::size_t i = 0; i < w.states.size(); ++i) out += (i ? "," : "") + w.states[i];
  if (with_contacts) {
    out += "],\"contacts\":[";
    for (std::size_t i = 0; i < w.contacts.size(); ++i) out += (i ? "," : "") + w.contacts[i];
  }
  return out + "],\"more\":" + (w.more ? "true" : "false") + "}\n";
}

}  // namespace

HttpAnswer recordedStates(const std::string& file, const std::string& name, const std::string& session,
                          const Query& q) {
  StatesAsk ask;
  if (const std::string why = readAsk(q, ask); !why.empty()) return errorAnswer(400, why);
  recording::McapReader r(file);
  std::optional<std::uint16_t> channel, contact_channel;
  for (const auto& [id, c] : r.channels()) {
    if (c.topic == "/" + session + "/state") channel = id;
    if (c.topic == "/" + session + "/contact") contact_channel = id;
  }
  if (!channel) return errorAnswer(404, "session: " + web::quoted(session) + " is not in " + web::quoted(name));
  Window w;
  if (ask.at) readInstant(r, *channel, *ask.at, w);
  else readWindow(r, *channel, contact_channel, ask, w);
  return {200, "application/json", windowJson(session, w, ask.with_contacts)};
}

HttpAnswer recordedEvents(const std::string& file, const std::string& name, const std::string& session) {
  recording::McapReader r(file);
  std::optional<std::uint16_t> channel;
  for (const auto& [id, c] : r.channels())
    if (c.topic == "/" + session + "/events") channel = id;
  if (!channel) return errorAnswer(404, "session: " + web::quoted(session) + " has no events in " + web::quoted(name));
  std::string out = "{\"session\":" + web::quoted(session) + ",\"events\":[";
  int n = 0;
  bool more = false;
  r.readMessages(
      [&](const recording::McapMessage& m) {
        if (n >= kMaxEvents || out.size() + m.data.size() > kMaxBody) {
          more = true;
          return;
        }
        out += (n++ ? "," : "") + m.data;
      },
      {*channel});
  return {200, "application/json", out + "],\"more\":" + (more ? "true" : "false") + "}\n"};
}

}  // namespace groundsim::web
