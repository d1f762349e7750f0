// The scenario's `objects` (obstacles) as the page draws them, read from
// the scene the bridge builds through the scenario layer anyway (scene
// view): each one's shape, size and placed pose (on_ground objects already
// stand on the ground there), so the page computes nothing physical.
#pragma once

#include <nlohmann/json.hpp>

#include "scenario/scenario.hpp"

namespace groundsim::web {

// [{"name","shape" (box/sphere/cylinder/capsule/cone),"static","mass",
//   "size" [x, y, z] full lengths (box, rounding included),"rounding",
//   "radius","height" (end to end),"top_radius","p" shape centre (m),
//   "q" shape to world (w x y z)}], in the model's order. Objects with mass
// move: contact_state_t carries their poses by name.
nlohmann::json objectsLayout(const Model& m, const State& s);

}  // namespace groundsim::web
