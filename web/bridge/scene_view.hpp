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
  nlohmann::json layout;         // {"vehicles": [...] (vehicleLayout in scene_view.cpp), "objects": [...] (object_layout.hpp)}
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
// neighbour's height). Nodes with no surface below get null.
nlohmann::json groundGrid(const Ground& g, double cx, double cy, int n, double step);

// One node: the height z with H(x, y, z) = 0 near z_start, or false.
bool surfaceHeight(const Ground& g, double x, double y, double z_start, double* z);

// A scenario copy with `count` copies of its first vehicle side by side
// along y (bounding circles `margin` m apart), for one car per player. Only
// the vehicles are read: the files the scenario names are not.
std::string withVehicles(const std::string& scenario_json, int count, double margin);

}  // namespace groundsim::web
