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

#include "physics/ground/ground.hpp"
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

// The track as the page draws it (a ribbon, web/src/track.js), in the joined
// message's layout (`track`): the centre line resampled every `s` step
// (1 m, coarser on tracks longer than 1.5 km), each station's position
// [x, y], unit normal to the left [nx, ny] (the tangent smoothed over 3 m
// each way, so a polyline's corners do not fold the ribbon's edges) and the
// ground's height at each lateral offset of `offsets` (every 1.5 m or less
// across [-half_width, half_width], solved from H(x, y, z) = 0 through the
// scenario's ground as the terrain's grids are), and the Coulomb mu at the
// centre (scene_mu where the ground has no say). Null without a centre line
// or a width.
nlohmann::json trackRibbon(const Ground& g, const scenario::RaceSpec& race, double scene_mu);

}  // namespace groundsim::web
