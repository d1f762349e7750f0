// The road car's hooks into a step (road_cars.cpp, road_car_controls.cpp):
// controls once per step, forces once per evaluation, and the parts of the
// semi-implicit integrators that advance its states.
#pragma once

#include <Eigen/Core>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

// Clamps the commanded controls, moves the steering at its rate and picks
// the gear (automatic, or as requested). Once per step.
void applyRoadCarControls(const Model& m, double dt, State& s);

// Tyre, suspension, powertrain, brake and drag forces of every road car at
// configuration y; overwrites its body's force and torque with the ones
// that give the accelerations of the body with its wheels sliding along the
// struts, and fills ws.aux_dot. h: the step the velocity-level brakes, ABS
// and traction control act over.
void applyRoadCars(const Model& m, const Eigen::VectorXd& y, double h, Workspace& ws);

// Semi-implicit update of the road-car states from the last evaluation:
// kick (travel rate and spin += k * rates) and drift (travel += h * rate,
// deflections from the slip velocities at the new body and wheel speeds).
void kickRoadCars(const Model& m, Eigen::VectorXd& y, const Workspace& ws, double k);
void driftRoadCars(const Model& m, Eigen::VectorXd& y, const Workspace& ws, double h);

}  // namespace groundsim
