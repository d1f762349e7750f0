// What a step applies of the commands (see State::applied and
// State::cars): wheel torques and steering at its rate, and a road car's
// clamped controls, steering and gear (controls.cpp).
#pragma once

#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"

namespace groundsim {

// Turns commands into what the actuators apply over dt: once per step, or,
// for an integrator that appliesControls(), once per substep over it.
void applyControls(const Model& m, double dt, State& s);

// Whether what the forces read of the controls (a wheel's or road car's
// steering, a road car's gear) differs in s from what it was (applied and
// cars as they were): an evaluation made before the change is stale after it.
bool controlsMoved(const std::vector<WheelControl>& applied, const std::vector<CarRuntime>& cars, const State& s);

}  // namespace groundsim
