// A race's bots set on a scenario document (docs/drivers.md, "Bots in
// sessions"): what the lobby's bots choice and `--bots` of the CLI's
// session commands do before a create is sent.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace groundsim::scenario {

// The k-th bot's vehicle name (k from 0): a name from a fixed roster with
// "-bot" after it, numbered past the roster's end.
std::string botName(int k);

struct BotsChoice {
  int count = 0;                     // [0, 64]; -1: the race's own bots
  std::optional<double> skill;       // race.bot_skill, [0.2, 1]
  std::optional<std::string> policy; // race.bot_policy: a file name as the scenario names its files
};

// Gives the document's race `choice.count` bots (-1: as many as it has): its own bots' vehicles
// (the last race.bots) are removed, and one copy of its first vehicle per
// bot is appended, named botName(k), placed behind it (the race's grid
// places every car it has a slot for); race.bots, bot_skill and bot_policy
// are set. Throws ScenarioError naming the field: no race section, no
// vehicle to copy, a count or skill out of range.
void setBots(nlohmann::json& doc, const BotsChoice& choice);

}  // namespace groundsim::scenario
