// Races on the page (docs/front-end.md, Races): the server publishes a race's
// layout, standings and happenings as events whose reason is "race: {json}"
// (docs/protocol.md, Race events). Every event is forwarded to the session's
// watchers as it comes; a RaceRelay keeps the last layout and standings of
// one session, so that a browser joining mid-race is sent them at once.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario/race_spec.hpp"

namespace groundsim::web {

class RaceRelay {
 public:
  // An event of the session: its reason and the message forwarded for it.
  void note(const std::string& reason, std::shared_ptr<const std::string> message);
  // What a browser that joins now is sent: the layout, then the standings
  // (each only when there is one).
  std::vector<std::shared_ptr<const std::string>> catchUp() const;

  // The type of a race event's reason ("race", "standings", "lap" ...), or "".
  static std::string type(const std::string& reason);

 private:
  std::shared_ptr<const std::string> layout_, standings_;
};

// A scenario's race as the page draws it, in the joined message's layout
// (`race`): what the server's "race" event says (laps, circuit, go, gates as
// [left x, left y, right x, right y]) and the track's centre line and half
// width. A browser joining at any time has it, whatever events it missed.
nlohmann::json raceLayout(const scenario::RaceSpec& race);

}  // namespace groundsim::web
