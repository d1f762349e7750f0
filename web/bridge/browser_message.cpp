#include "protocol/text.hpp"
#include "bridge/browser_message.hpp"

#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "bridge/shipped_scenarios.hpp"

namespace groundsim::web {
namespace {

using nlohmann::json;

struct Refused {
  MessageError e;
};

[[noreturn]] void refuse(const std::string& field, const std::string& reason) { throw Refused{{field, reason}}; }

std::string shown(const json& v) {
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

// Reads the fields of one op and refuses any it does not know.
class Fields {
 public:
  explicit Fields(const json& obj) : obj_(obj) {}
  ~Fields() = default;

  const json* get(const std::string& key) {
    seen_.insert(key);
    auto it = obj_.find(key);
    return it == obj_.end() ? nullptr : &*it;
  }
  double number(const std::string& key, double lo, double hi, std::optional<double> def) {
    const json* v = get(key);
    if (!v) {
      if (def) return *def;
      refuse("/" + key, "missing (a number in [" + net::number(lo) + ", " + net::number(hi) + "])");
    }
    if (!v->is_number()) refuse("/" + key, "must be a number, got " + shown(*v));
    const double x = v->get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
      refuse("/" + key, "must be in [" + net::number(lo) + ", " + net::number(hi) + "], got " + shown(*v));
    return x;
  }
  int integer(const std::string& key, int lo, int hi, int def) {
    const json* v = get(key);
    if (!v) return def;
    if (!v->is_number_integer()) refuse("/" + key, "must be an integer, got " + shown(*v));
    const auto x = v->get<long long>();
    if (x < lo || x > hi) refuse("/" + key, "must be in [" + net::number(lo) + ", " + net::number(hi) + "], got " + shown(*v));
    return static_cast<int>(x);
  }
  bool boolean(const std::string& key, bool def) {
    const json* v = get(key);
    if (!v) return def;
    if (!v->is_boolean()) refuse("/" + key, "must be true or false, got " + shown(*v));
    return v->get<bool>();
  }
  std::string string(const std::string& key, std::size_t max_len, std::optional<std::string> def) {
    const json* v = get(key);
    if (!v) {
      if (def) return *def;
      refuse("/" + key, "missing (a string)");
    }
    if (!v->is_string()) refuse("/" + key, "must be a string, got " + shown(*v));
    std::string s = v->get<std::string>();
    if (s.size() > max_len) refuse("/" + key, "longer than " + std::to_string(max_len) + " characters");
    return s;
  }
  void noOthers() {
    for (auto it = obj_.begin(); it != obj_.end(); ++it)
      if (!seen_.count(it.key())) refuse("/" + it.key(), "unknown field");
  }

 private:
  const json& obj_;
  std::set<std::string> seen_{"op"};
};

// A player's name: at most 24 bytes of printable text (UTF-8 beyond ASCII
// allowed), no control characters; "" when absent.
std::string playerName(Fields& f) {
  std::string s = f.string("player", 24, std::string());
  for (unsigned char c : s)
    if (c < 0x20 || c == 0x7f) refuse("/player", "must be printable text (no control characters)");
  return s;
}

BrowserMessage readOp(const std::string& op, Fields& f) {
  if (op == "create") {
    CreateMsg m;
    m.config = f.string("config", 128, std::nullopt);
    if (!validConfigId(m.config))
      refuse("/config", "must be a shipped scenario's path under the configs folder (*.json, no \"..\"), got \"" +
                            m.config + "\"");
    m.mode = f.string("mode", 16, std::string("realtime"));
    if (m.mode != "realtime" && m.mode != "fast" && m.mode != "lockstep")
      refuse("/mode", "must be realtime, fast or lockstep, got \"" + m.mode + "\"");
    m.publish_rate = f.number("publish_rate", 0, 1000, 0.0);
    m.vehicles = f.integer("vehicles", 0, kMaxCreateVehicles, 0);
    m.bots = f.integer("bots", -1, kMaxCreateBots, -1);
    m.bot_skill = f.number("bot_skill", 0.0, 1.0, 0.0);
    if (m.bot_skill != 0.0 && m.bot_skill < 0.2) refuse("/bot_skill", "must be 0 (the scenario's) or in [0.2, 1]");
    m.drive = f.boolean("drive", true);
    m.player = playerName(f);
    return m;
  }
  if (op == "join") {
    JoinMsg m;
    m.session = f.string("session", 16, std::nullopt);
    if (!validSessionId(m.session)) refuse("/session", "must be 8 upper-case hex digits, got \"" + m.session + "\"");
    const std::string role = f.string("role", 16, std::string("spectate"));
    if (role != "drive" && role != "spectate") refuse("/role", "must be drive or spectate, got \"" + role + "\"");
    m.role = role == "drive" ? Role::Drive : Role::Spectate;
    m.vehicle = f.integer("vehicle", -1, 31, -1);
    m.player = playerName(f);
    return m;
  }
  if (op == "controls") {
    ControlsMsg m;
    m.controls.throttle = f.number("throttle", 0, 1, 0.0);
    m.controls.brake = f.number("brake", 0, 1, 0.0);
    m.controls.steer = f.number("steer", -1, 1, 0.0);
    m.controls.handbrake = f.boolean("handbrake", false);
    m.controls.gear = f.integer("gear", -1, 1, 1);
    m.seq = f.number("seq", 0, 9e15, 0.0);
    return m;
  }
  if (op == "ground") {
    GroundMsg m;
    m.cx = f.number("cx", -1e6, 1e6, std::nullopt);
    m.cy = f.number("cy", -1e6, 1e6, std::nullopt);
    return m;
  }
  if (op == "reset" || op == "pause" || op == "resume" || op == "respawn") return SessionOpMsg{op};
  if (op == "leave") return LeaveMsg{};
  if (op == "ping") return PingMsg{f.number("t", -1e300, 1e300, 0.0)};
  if (op == "preview") {
    PreviewMsg m;
    m.config = f.string("config", 128, std::nullopt);
    if (!validConfigId(m.config)) refuse("/config", "must be a shipped scenario's path under the configs folder, got \"" + m.config + "\"");
    return m;
  }
  refuse("/op", "unknown op \"" + op + "\" (create, join, controls, ground, reset, respawn, pause, resume, leave, ping, preview)");
}

}  // namespace

bool validSessionId(const std::string& id) {
  if (id.size() != 8) return false;
  for (char c : id)
    if (!((c >= '0' && c <= '9') || (c >= 'A' && c <= 'F'))) return false;
  return true;
}

ParsedMessage parseBrowserMessage(const std::string& text) {
  ParsedMessage out;
  if (text.size() > kMaxMessageBytes) {
    out.error = {"", "message of " + std::to_string(text.size()) + " bytes exceeds the limit of " +
                         std::to_string(kMaxMessageBytes)};
    return out;
  }
  // the callback sees every nesting level before it is built: deeper
  // documents are cut off without recursing further
  bool too_deep = false;
  json doc = json::parse(
      text,
      [&](int depth, json::parse_event_t, json&) {
        if (depth > kMaxMessageDepth) too_deep = true;
        return !too_deep;
      },
      false);
  if (too_deep) {
    out.error = {"", "nested deeper than " + std::to_string(kMaxMessageDepth) + " levels"};
    return out;
  }
  if (doc.is_discarded()) {
    out.error = {"", "not valid JSON"};
    return out;
  }
  if (!doc.is_object()) {
    out.error = {"", "must be a JSON object with an \"op\" field"};
    return out;
  }
  try {
    auto it = doc.find("op");
    if (it == doc.end()) refuse("/op", "missing");
    if (!it->is_string()) refuse("/op", "must be a string, got " + shown(*it));
    out.op = it->get<std::string>();
    Fields f(doc);
    BrowserMessage m = readOp(out.op, f);
    f.noOthers();
    out.message = std::move(m);
  } catch (const Refused& r) {
    out.error = r.e;
  }
  return out;
}

}  // namespace groundsim::web
