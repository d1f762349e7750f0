#include "bridge/race_relay.hpp"

#include <nlohmann/json.hpp>

namespace groundsim::web {

std::string RaceRelay::type(const std::string& reason) {
  if (reason.rfind("race: {", 0) != 0) return "";
  // events are few (gates, laps): parsing each is cheap
  const nlohmann::json j = nlohmann::json::parse(reason.begin() + 6, reason.end(), nullptr, false);
  if (!j.is_object()) return "";
  auto t = j.find("type");
  return t != j.end() && t->is_string() ? t->get<std::string>() : "";
}

void RaceRelay::note(const std::string& reason, std::shared_ptr<const std::string> message) {
  const std::string t = type(reason);
  if (t == "race") {
    layout_ = std::move(message);
    standings_.reset();  // a new race (or a reset) starts over
  } else if (t == "standings") {
    standings_ = std::move(message);
  }
}

std::vector<std::shared_ptr<const std::string>> RaceRelay::catchUp() const {
  std::vector<std::shared_ptr<const std::string>> out;
  if (layout_) out.push_back(layout_);
  if (standings_) out.push_back(standings_);
  return out;
}

nlohmann::json raceLayout(const scenario::RaceSpec& race) {
  nlohmann::json gates = nlohmann::json::array(), line = nlohmann::json::array();
  for (const auto& g : race.gates) gates.push_back({g.left[0], g.left[1], g.right[0], g.right[1]});
  for (const auto& p : race.centerline) line.push_back({p[0], p[1]});
  return {{"type", "race"}, {"laps", race.laps}, {"circuit", race.circuit}, {"go", race.countdown},
          {"gates", std::move(gates)}, {"centerline", std::move(line)}, {"half_width", race.half_width}};
}

}  // namespace groundsim::web
