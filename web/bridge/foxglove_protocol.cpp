#include "bridge/foxglove_protocol.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

namespace groundsim::web::foxglove {

using nlohmann::json;

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// A value as a refusal shows it: short, so an echo of a hostile message
// stays small.
std::string shown(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

struct Refusal {
  ClientError e;
};
[[noreturn]] void refuse(std::string field, std::string reason) { throw Refusal{{std::move(field), std::move(reason)}}; }

// An unsigned integer field of at most `max` (JSON numbers are doubles to
// some clients: 3.0 is accepted, 3.5 is not).
std::uint64_t unsignedField(const json& obj, const std::string& key, const std::string& at, std::uint64_t max) {
  const auto it = obj.find(key);
  if (it == obj.end()) refuse(at + "/" + key, "missing (an unsigned integer)");
  const json& v = *it;
  if (v.is_number_unsigned()) {
    const auto x = v.get<std::uint64_t>();
    if (x > max) refuse(at + "/" + key, "at most " + std::to_string(max) + ", got " + shown(v));
    return x;
  }
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && d >= 0 && d <= static_cast<double>(max) && d == std::floor(d))
      return static_cast<std::uint64_t>(d);
  }
  refuse(at + "/" + key, "must be an unsigned integer up to " + std::to_string(max) + ", got " + shown(v));
}

const json& arrayField(const json& obj, const std::string& key) {
  const auto it = obj.find(key);
  if (it == obj.end()) refuse("/" + key, "missing (an array)");
  if (!it->is_array()) refuse("/" + key, "must be an array, got " + shown(*it));
  if (it->size() > kMaxEntries)
    refuse("/" + key, "at most " + std::to_string(kMaxEntries) + " entries, got " + std::to_string(it->size()));
  return *it;
}

constexpr std::uint64_t kMaxU32 = 0xffffffffu;
// channel ids are u64 on the wire, but a JavaScript client cannot hold more than 2^53 exactly
constexpr std::uint64_t kMaxChannelId = (std::uint64_t{1} << 53) - 1;

ClientMessage parseObject(const json& m) {
  if (!m.is_object()) refuse("", "must be a JSON object with an \"op\", got " + shown(m));
  const auto op_it = m.find("op");
  if (op_it == m.end()) refuse("/op", "missing (a string)");
  if (!op_it->is_string()) refuse("/op", "must be a string, got " + shown(*op_it));
  const std::string op = op_it->get<std::string>();
  if (op == "subscribe") {
    Subscribe s;
    const json& list = arrayField(m, "subscriptions");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string at = "/subscriptions/" + std::to_string(i);
      if (!list[i].is_object()) refuse(at, "must be an object {id, channelId}, got " + shown(list[i]));
      Subscription sub;
      sub.id = static_cast<std::uint32_t>(unsignedField(list[i], "id", at, kMaxU32));
      sub.channel = unsignedField(list[i], "channelId", at, kMaxChannelId);
      s.subscriptions.push_back(sub);
    }
    return s;
  }
  if (op == "unsubscribe") {
    Unsubscribe u;
    const json& list = arrayField(m, "subscriptionIds");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const json& v = list[i];
      const std::string at = "/subscriptionIds/" + std::to_string(i);
      if (!v.is_number_unsigned() || v.get<std::uint64_t>() > kMaxU32)
        refuse(at, "must be an unsigned 32-bit integer, got " + shown(v));
      u.ids.push_back(static_cast<std::uint32_t>(v.get<std::uint64_t>()));
    }
    return u;
  }
  // the protocol's other client messages need capabilities this server does not declare
  static const char* const kNeedsCapability[][2] = {
      {"advertise", "clientPublish"},           {"unadvertise", "clientPublish"},
      {"getParameters", "parameters"},          {"setParameters", "parameters"},
      {"subscribeParameterUpdates", "parametersSubscribe"},
      {"unsubscribeParameterUpdates", "parametersSubscribe"},
      {"subscribeConnectionGraph", "connectionGraph"},
      {"unsubscribeConnectionGraph", "connectionGraph"},
      {"fetchAsset", "assets"},                 {"playbackControlRequest", "playbackControl"}};
  for (const auto& [name, capability] : kNeedsCapability)
    if (op == name)
      refuse("/op", "\"" + op + "\" needs the capability " + capability + ", which this server does not offer");
  refuse("/op", "unknown op " + shown(*op_it) + " (this server accepts subscribe and unsubscribe)");
}

}  // namespace

std::optional<std::string> chooseSubprotocol(const std::vector<std::string_view>& headers) {
  bool sdk = false, legacy = false;
  for (std::string_view h : headers) {
    while (!h.empty()) {
      const auto comma = h.find(',');
      const std::string_view item = trim(h.substr(0, comma));
      sdk = sdk || item == kSdkSubprotocol;
      legacy = legacy || item == kLegacySubprotocol;
      if (comma == std::string_view::npos) break;
      h.remove_prefix(comma + 1);
    }
  }
  if (sdk) return std::string(kSdkSubprotocol);
  if (legacy) return std::string(kLegacySubprotocol);
  return std::nullopt;
}

std::string serverInfo(const std::string& name, const std::string& session_id,
                       const std::map<std::string, std::string>& metadata) {
  // no capabilities: clients only subscribe (see kNeedsCapability)
  return json{{"op", "serverInfo"},
              {"name", name},
              {"capabilities", json::array()},
              {"metadata", metadata},
              {"sessionId", session_id}}
      .dump();
}

std::string advertise(const std::vector<const Channel*>& channels) {
  json list = json::array();
  for (const Channel* c : channels) {
    json j = {{"id", c->id},
              {"topic", c->topic},
              {"encoding", "json"},
              {"schemaName", c->schema_name},
              {"schemaEncoding", "jsonschema"},
              {"schema", c->schema}};
    if (!c->metadata.empty()) j["metadata"] = c->metadata;
    list.push_back(std::move(j));
  }
  return json{{"op", "advertise"}, {"channels", std::move(list)}}.dump();
}

std::string unadvertise(const std::vector<std::uint64_t>& ids) {
  return json{{"op", "unadvertise"}, {"channelIds", ids}}.dump();
}

std::string status(Level level, const std::string& message) {
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump(
      -1, ' ', false, json::error_handler_t::replace);
}

std::array<std::uint8_t, kDataHeaderBytes> dataHeader(std::uint32_t subscription, std::uint64_t ns) {
  std::array<std::uint8_t, kDataHeaderBytes> h{};
  h[0] = 0x01;
  for (int i = 0; i < 4; ++i) h[1 + i] = static_cast<std::uint8_t>(subscription >> (8 * i));
  for (int i = 0; i < 8; ++i) h[5 + i] = static_cast<std::uint8_t>(ns >> (8 * i));
  return h;
}

std::string ClientError::text() const {
  return field.empty() ? "refused: " + reason : "refused " + field + ": " + reason;
}

ClientMessage parseClientMessage(std::string_view text) {
  json m;
  try {
    m = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    return ClientError{"", "malformed JSON (at byte " + std::to_string(e.byte) + ")"};
  }
  try {
    return parseObject(m);
  } catch (const Refusal& r) {
    return r.e;
  }
}

}  // namespace groundsim::web::foxglove
