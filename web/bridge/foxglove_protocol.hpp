// The Foxglove WebSocket protocol's messages as the bridge speaks them: the
// subprotocol handshake, the server's JSON messages (serverInfo, advertise,
// unadvertise, status), the binary message-data frame, and the two client
// messages it accepts (subscribe, unsubscribe), parsed with errors that name
// the offending field. No sockets here: foxglove_server.hpp does the I/O.
//
// The spec: foxglove/ws-protocol docs/spec.md (subprotocol
// foxglove.websocket.v1, deprecated) and the Foxglove SDK's server
// (foxglove/foxglove-sdk rust/foxglove/src/protocol/v1 and
// websocket/handshake.rs), which accepts only foxglove.sdk.v1 with the same
// v1 messages. Both are accepted; the subset used here (no client publish,
// parameters, services, assets, time or playback control) is the same in
// both, so the choice only changes the handshake's answer.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace groundsim::web::foxglove {

// The subprotocols accepted, in the server's order of preference.
inline constexpr const char* kSdkSubprotocol = "foxglove.sdk.v1";          // the Foxglove SDK, today's app
inline constexpr const char* kLegacySubprotocol = "foxglove.websocket.v1";  // ws-protocol, Lichtblick
// The subprotocol to answer a Sec-WebSocket-Protocol header with (one or
// more comma-separated lists, as a client may send), or none: the server
// prefers foxglove.sdk.v1 when a client offers both.
std::optional<std::string> chooseSubprotocol(const std::vector<std::string_view>& headers);

// One channel as advertised: a topic of a session's stream.
struct Channel {
  std::uint64_t id = 0;
  std::string topic;        // "/<session>/state", the MCAP recorder's topic names
  std::string schema_name;  // "groundsim.state"
  std::string schema;       // JSON Schema text (schemaEncoding "jsonschema")
  std::map<std::string, std::string> metadata;
};

// JSON text messages of the server.
std::string serverInfo(const std::string& name, const std::string& session_id,
                       const std::map<std::string, std::string>& metadata);
std::string advertise(const std::vector<const Channel*>& channels);
std::string unadvertise(const std::vector<std::uint64_t>& ids);
enum class Level { Info = 0, Warning = 1, Error = 2 };
std::string status(Level level, const std::string& message);

// A binary message-data frame's header: opcode 0x01, the client's
// subscription id (u32) and the timestamp (u64 ns), little-endian; the
// payload (the message's JSON) follows it in the same WebSocket message.
inline constexpr std::size_t kDataHeaderBytes = 1 + 4 + 8;
std::array<std::uint8_t, kDataHeaderBytes> dataHeader(std::uint32_t subscription, std::uint64_t ns);

// What a client may send.
struct Subscription {
  std::uint32_t id = 0;
  std::uint64_t channel = 0;
};
struct Subscribe {
  std::vector<Subscription> subscriptions;
};
struct Unsubscribe {
  std::vector<std::uint32_t> ids;
};
// A refused message: `field` is a JSON pointer into it ("" for the whole
// message, "/op", "/subscriptions/2/channelId"), `reason` says what is wrong.
struct ClientError {
  std::string field;
  std::string reason;
  std::string text() const;  // what the status message says
};
using ClientMessage = std::variant<Subscribe, Unsubscribe, ClientError>;
// Parses a text message. Only syntax and types are checked here; whether a
// channel or subscription exists is the server's to say.
ClientMessage parseClientMessage(std::string_view text);
// At most this many entries in one subscribe or unsubscribe.
inline constexpr std::size_t kMaxEntries = 4096;

}  // namespace groundsim::web::foxglove
