// Contact between bodies as its own phase of a semi-implicit Euler step
// (contact_phase.cpp; docs/contact.md, "The contact phase"): the stiff
// contact of the step's pairs takes the substeps it needs, every other
// force is evaluated once.
#pragma once

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

// Whether this step can take the contact phase: semi-implicit Euler with
// no substeps of its own (m.opt.substeps, m.object_substeps), the step's
// census taken (contactSubsteps), and every candidate pair between road
// cars whose tyres are slip tyres, or a road car and a static group. The
// rest (objects with mass, the report's cars of mass points, stick-slip
// tyres, other integrators) take the step in whole substeps.
bool contactPhaseApplies(const Model& m, const Workspace& ws);

// One semi-implicit Euler step of dt whose contact between bodies takes n
// substeps: every force but that contact at the step's start, once (the
// road cars' tyres, suspension and powertrain, gravity, the ground); the
// bodies of no pair take the step with them; the cars of the pairs take n
// substeps of dt / n, each with the contact at its own configuration
// through the car's constant body-frame reduced mass (the same response
// the full evaluation gives an external force) and the rest held; then the
// road cars' travel and tyre deflections drift over dt.
void contactPhaseStep(const Model& m, State& s, Workspace& ws, double dt, int n);

}  // namespace groundsim
