// Energy, momentum and divergence checks. Not called inside the force loop;
// the simulator samples them (health every step is cheap, energy every
// kEnergyCheckInterval steps).
#pragma once

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

struct Energy {
  double kinetic = 0.0;   // J  translational + rotational
  double gravity = 0.0;   // J  -m g . x
  double spring = 0.0;    // J  1/2 k (l - l0)^2
  double ground = 0.0;    // J  1/2 S depth^2
  double contact = 0.0;   // J  1/2 S depth^2 of probes inside other bodies' shapes
  double total() const { return kinetic + gravity + spring + ground + contact; }
};

// Recomputes kinematics and contacts of s into scratch: pass a scratch that
// is not the step's (Workspace::diagnostics), or its last force evaluation
// is overwritten.
Energy computeEnergy(const Model& m, const State& s, Workspace& scratch);
Vec3 linearMomentum(const Model& m, const State& s);
// world angular velocity of a body at state s
Vec3 angularVelocity(const Model& m, const State& s, int body);
// about the world origin
Vec3 angularMomentum(const Model& m, const State& s);

// Sets s.health / s.health_reason if s has diverged: a non-finite state,
// penetration or speed beyond model limits (ws holds the last force
// evaluation), or, when check_energy, energy above the initial energy plus
// drive work by more than the limit (computed in ws.diagnostics, so ws's
// force buffers are left as they are). True while healthy.
bool checkHealth(const Model& m, State& s, Workspace& ws, bool check_energy);

}  // namespace groundsim
