// The contact-between-bodies phase of a force evaluation (body_contact.cpp).
#pragma once

#include <Eigen/Core>

#include "physics/core/model.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

// After the kinematics and accumulateBodyForces: finds the pairs of groups
// whose boxes overlap and adds the contact force of every probe inside a
// shape of the other group to both bodies (apply = false: only measures
// energy, depth and ws.pair_contacts, for diagnostics).
void bodyContacts(const Model& m, bool apply, Workspace& ws);
// No contact between bodies this evaluation: its telemetry cleared.
void clearBodyContacts(Workspace& ws);

// The broad phase alone at configuration y (no kinematics needed), each
// group's box padded by what it can move in dt: whether any pair of groups
// may touch during the step. The specialised step paths run only while
// none may; the step's force evaluations then reuse its pairs
// (Workspace::step_pairs).
bool groupsMayTouch(const Model& m, const Eigen::VectorXd& y, double dt, Workspace& ws);

// Integrator substeps per step of dt that resolve (substepsFor) the
// contact of every candidate pair of the last groupsMayTouch at
// configuration y. For two rigid (or static) groups, from a census of the
// probes inside the other's shapes or within the step's reach of them:
// their stiffest mode is bounded by the sum of the inverse masses (with the
// lever arms) they meet along the normals. Otherwise from the pair's
// reduced mass with the face probes of both groups pressing at once. 1
// when no pair may touch. Keeps the census's probes in ws (census,
// census_range) and, when the step's pairs are set (step_pairs), sets
// step_census: the step's force evaluations then test only the probes the
// census found pressing or within the step's reach (the rest cannot touch
// in the step), and every other pair's probes as before.
int contactSubsteps(const Model& m, const Eigen::VectorXd& y, Workspace& ws, double dt);

// The face-probe bound at dt (every face probe of both groups pressing at
// once, on the reduced mass) over every pair of groups that can touch (one
// of them movable), and the objects' own (Model::object_substeps): the
// accuracy pilot's floor of contact substeps. contactSubsteps takes it for
// pairs that are not both rigid; for rigid pairs the census usually takes
// fewer, and can take more where lever arms weigh. 1 for a scene without
// contact between bodies.
int contactSubstepsBound(const Model& m, double dt);

}  // namespace groundsim
