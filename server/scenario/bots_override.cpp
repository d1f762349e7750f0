#include "scenario/bots_override.hpp"

#include <algorithm>
#include <array>

#include "scenario/race_spec.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::scenario {

std::string botName(int k) {
  static const std::array<const char*, 12> roster = {"ada",  "bruno", "carla", "dev",  "emil", "fumi",
                                                     "gus",  "hana",  "ivo",   "june", "kai",  "lena"};
  const int n = static_cast<int>(roster.size());
  if (k >= 0 && k < n) return std::string(roster[static_cast<size_t>(k)]) + "-bot";
  return "bot-" + std::to_string(k + 1);
}

void setBots(nlohmann::json& doc, const BotsChoice& choice) {
  auto refuse = [](const std::string& where, const std::string& why) { throw ScenarioError({Issue{where, why}}); };
  if (!doc.is_object() || !doc.contains("race") || !doc["race"].is_object())
    refuse("/race", "bots drive in a race: this scenario has no race section");
  if (choice.count < -1 || choice.count > kMaxGridSlots)
    refuse("/race/bots", "expected 0 to " + std::to_string(kMaxGridSlots) + " bots, got " + std::to_string(choice.count));
  if (choice.skill && !(*choice.skill >= 0.2 && *choice.skill <= 1.0))
    refuse("/race/bot_skill", "expected a skill in [0.2, 1], got " + std::to_string(*choice.skill));
  nlohmann::json& race = doc["race"];
  // the vehicles as a list
  nlohmann::json list = nlohmann::json::array();
  if (doc.contains("vehicles") && doc["vehicles"].is_array()) list = doc["vehicles"];
  else if (doc.contains("vehicle") && doc["vehicle"].is_object()) list.push_back(doc["vehicle"]);
  if (list.empty() || !list[0].is_object()) refuse("/vehicles", "no vehicle to copy for the bots");
  const int had = race.contains("bots") && race["bots"].is_number_integer() ? race["bots"].get<int>() : 0;
  const int count = choice.count >= 0 ? choice.count : std::clamp(had, 0, kMaxGridSlots);
  const int players = std::max(1, static_cast<int>(list.size()) - std::clamp(had, 0, static_cast<int>(list.size())));
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < players; ++i) out.push_back(list[static_cast<size_t>(i)]);
  for (int k = 0; k < count; ++k) {
    nlohmann::json v = list[0];
    v["name"] = botName(k);
    nlohmann::json& init = v["initial"];
    if (!init.is_object()) init = nlohmann::json::object();
    nlohmann::json pos = init.contains("position") && init["position"].is_array() && init["position"].size() == 3
                             ? init["position"]
                             : nlohmann::json::array({0.0, 0.0, 0.0});
    // behind the first car, two abreast, where no grid slot places them
    const double x = pos[0].is_number() ? pos[0].get<double>() : 0.0, y = pos[1].is_number() ? pos[1].get<double>() : 0.0;
    pos[0] = x - 7.0 * (k / 2 + 1);
    pos[1] = y + (k % 2 == 0 ? 0.0 : -5.0);
    init["position"] = pos;
    out.push_back(v);
  }
  doc.erase("vehicle");
  doc["vehicles"] = std::move(out);
  race["bots"] = count;
  if (choice.skill) race["bot_skill"] = *choice.skill;
  if (choice.policy) race["bot_policy"] = *choice.policy;
}

}  // namespace groundsim::scenario
