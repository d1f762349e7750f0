// The shipped scenarios a browser may create sessions from: every *.json
// under the bridge's configs folder, subfolders included, named by its path
// relative to that folder ("plain.json", "tasks/goal.json"), with what the
// lobby shows of each: its description and how many cars a session of it
// can host.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace groundsim::web {

struct ShippedScenario {
  std::string id;           // path under the configs folder, '/'-separated: what a create names
  std::string name;         // the scenario's "name"
  std::string description;  // its "description" ("" when it has none)
  int vehicles = 1;         // its own vehicles (a create with "vehicles": 0)
  double output_rate = 50;  // Hz: its states published (a create with publish_rate 0)
  int min_cars = 1;         // the cars a create may ask for (vehicles 0 or n copies of its car)
  int max_cars = 1;
  std::string limit;        // why no more than max_cars: the first refusal, or the cap
  bool race = false;        // it has a race section: the lobby offers bots for it
  int bots = 0;             // its race's own bots (race.bots)
  int grid = 0;             // its race's grid slots
};

struct ShippedList {
  std::vector<ShippedScenario> scenarios;  // top-level files first, then by id
  std::vector<std::string> skipped;        // "id: reason" for files not offered
};

// Capacity: a session holds the scenario's own vehicles, or n copies of its
// first car side by side (withVehicles, `margin` m apart), n = 1 ... max_cars,
// as far as the copies pass the scenario layer's validation (budget, overlap,
// a task's vehicle, with max_cars as the budget's vehicle limit); heightfield
// files are read from the scenario's folder. A file that does not validate
// as it is is not offered. Ids are at most 128 characters of
// [A-Za-z0-9._-/] (what a create's "config" may hold: validConfigId).
ShippedList listShippedScenarios(const std::string& dir, double margin, int max_cars);

// A create's "config": a relative path of [A-Za-z0-9._-] parts joined by
// '/', ending in .json, without "." or ".." parts; at most 128 characters.
bool validConfigId(const std::string& id);

// What the lobby's card of a shipped scenario draws its picture from (the
// page renders it, web/src/preview.js): the ground's heights and surfaces
// on an n x n grid (groundGrid, solved through the scenario's ground as the
// page's terrain is) over a square that holds the race track (its centre
// line and half width plus 12 m), else the vehicles' start and the objects
// (plus 30 m); the track {centerline, half_width, closed}, the objects'
// footprints [x, y, length, width, yaw] (a box's; a disc's diameter twice
// for other shapes) and the cars' starts [x, y, yaw] in it. Throws what the
// scenario layer throws for a file that does not build.
nlohmann::json scenarioPreview(const std::string& dir, const std::string& id, int n = 48);

}  // namespace groundsim::web
