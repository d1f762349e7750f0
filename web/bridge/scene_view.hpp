// What the page needs to draw a session, computed here through the scenario
// layer so the browser never re-implements the ground or the car:
//  - the layout of each vehicle (points and springs of the report's figure 1,
//    the wheels' placement on the body, their radius and radial stiffness),
//    sent once when a browser joins, with the scenario's objects as placed;
//  - height grids of the ground H(x, y, z) = 0 around a point, sent as the
//    followed vehicle moves.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario/scenario.hpp"

namespace groundsim::web {

struct SceneView {
  std::string scenario_json;     // the document as given
  std::string name;
  nlohmann::json layout;         // {"vehicles": [...] (vehicleLayout in scene_view.cpp), "objects": [...] (object_layout.hpp),
                                 //  "friction": contact.friction, "horizon": [...] (horizonGrids)}
  std::vector<int> wheels;       // wheel count per vehicle (drive_t.nwheels)
  std::vector<bool> road_car;    // per vehicle: kind "road_car", driven with controls_t
  GroundPtr ground;              // this view's own instance: use from one thread at a time
};

// Parses, validates and builds the scenario (throws scenario::ScenarioError).
// Files the scenario names are read under `files` (the bridge: the assets
// it sent or knows by hash).
std::shared_ptr<SceneView> makeSceneView(const std::string& scenario_json,
                                         const scenario::FileAccess& files = scenario::FileAccess::none());

// Heights of the ground on an n x n grid of spacing `step` centred on the
// grid node nearest (cx, cy): z[i * n + j] at x = x0 + j step, y = y0 + i step,
// solving H(x, y, z) = 0 for z (Newton guarded by bisection, started from the
// neighbour's height). Nodes with no surface below get null. "mu": each
// node's Coulomb mu, null where the ground has no say (the scene's
// contact.friction applies), only when the ground has patches or a map there.
nlohmann::json groundGrid(const Ground& g, double cx, double cy, int n, double step);

// The ground far from the car, for a horizon: `levels` grids of n x n
// nodes, centred on the grid node nearest (cx, cy), the first of spacing
// step0 and each next 4 times coarser (65 nodes from 4 m: 256 m, 1 km, 4 km
// and 16 km across), as groundGrid's; a node's height is the mean of 2 x 2
// samples a quarter step from it. "mu" (a node's Coulomb mu, scene_mu
// where the ground has no say) only when the ground has friction patches or
// a map on the level.
nlohmann::json horizonGrids(const Ground& g, double cx, double cy, double scene_mu, int n = 65, double step0 = 4.0,
                            int levels = 4);

// One node: the height z with H(x, y, z) = 0 near z_start, or false.
bool surfaceHeight(const Ground& g, double x, double y, double z_start, double* z);

// A scenario copy with `count` copies of its first vehicle side by side
// along y (bounding circles `margin` m apart), for one car per player, and
// after them one more for each of its race's bots (`race.bots`, named
// bot-1, bot-2, ...: the session's classical drivers take the last cars).
// Only the vehicles are read: the files the scenario names are not.
std::string withVehicles(const std::string& scenario_json, int count, double margin);
// A race scenario with `bots` bots (-1: its own count) at `skill` (0: its
// own), as the lobby's race button asks (scenario::setBots); throws
// ScenarioError naming the field.
std::string withBots(const std::string& scenario_json, int bots, double skill);

}  // namespace groundsim::web
