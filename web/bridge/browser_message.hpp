// Messages from a browser: JSON text, one object with an "op" field.
// Everything a browser sends is hostile until checked here: the text's size
// and nesting depth are bounded before and while parsing, every field is
// checked for type and range, and unknown fields are refused. A refusal
// names the field as a JSON pointer and the reason.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <variant>

#include "bridge/controls.hpp"

namespace groundsim::web {

inline constexpr std::size_t kMaxMessageBytes = 4096;
inline constexpr int kMaxMessageDepth = 4;
// the most cars a create may ask for ("vehicles"); the lobby offers no more
inline constexpr int kMaxCreateVehicles = 8;
// the most bots a create may ask for ("bots"): with one player, a grid of 8
inline constexpr int kMaxCreateBots = 7;

enum class Role { Drive, Spectate };

struct CreateMsg {
  std::string config;          // a scenario of the bridge's config folder: its path there ("tasks/goal.json")
  std::string mode = "realtime";
  double publish_rate = 0.0;   // Hz, 0: the scenario's
  int vehicles = 0;            // 0: the scenario's; n > 0 puts n copies of its car side by side
  int bots = -1;               // a race: -1 the scenario's bots, else this many (race.bots; docs/drivers.md)
  double bot_skill = 0.0;      // a race's bots' skill in [0.2, 1]; 0: the scenario's
  bool drive = true;           // join it as its first driver
  std::string player;          // the player's name as others see it ("" : none given); printable, <= 24 bytes
};
struct JoinMsg {
  std::string session;
  Role role = Role::Spectate;
  int vehicle = -1;            // -1: the first free one
  std::string player;          // as in CreateMsg
};
struct ControlsMsg {
  Controls controls;
  double seq = 0;              // the page's count; the latency trace pairs it with drive_t's seq
};
struct GroundMsg {
  double cx = 0, cy = 0;       // m, centre of the grid wanted
};
struct SessionOpMsg {
  std::string op;              // "reset" | "pause" | "resume" | "respawn" (a race's: the driver's car)
};
struct LeaveMsg {};
struct PingMsg {
  double t = 0;
};
struct PreviewMsg {
  std::string config;          // a shipped scenario: what its lobby card's picture is drawn from
};

using BrowserMessage =
    std::variant<CreateMsg, JoinMsg, ControlsMsg, GroundMsg, SessionOpMsg, LeaveMsg, PingMsg, PreviewMsg>;

struct MessageError {
  std::string field;   // JSON pointer, "" for the text itself
  std::string reason;
};

struct ParsedMessage {
  std::optional<BrowserMessage> message;
  MessageError error;  // when !message
  std::string op;      // the op, when it could be read
};

ParsedMessage parseBrowserMessage(const std::string& text);

bool validSessionId(const std::string& id);

}  // namespace groundsim::web
