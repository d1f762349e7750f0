// The other wheel and tyre models the core offers for a scene's vehicles:
// what the pilot may substitute for the user's model where the substitute's
// own converged solution is within a fraction of the tolerance of the
// user's (pilot.cpp; docs/accuracy.md, "Model fidelity"). Found from what
// each vehicle is (its kind and model fields), never from a config's name.
#pragma once

#include <string>
#include <vector>

#include "scenario/scenario.hpp"

namespace groundsim::accuracy {

struct ModelOption {
  std::string name;  // short: "circle wheels", "stick-slip tyres"
  std::string what;  // each vehicle changed: "car: 20-point rims on rim springs -> circle on a bearing"
  scenario::Scenario scenario;  // s with the vehicles' models swapped (its document says so)
  // the integrators worth piloting on it beyond the one that bounds its gap
  // (empty: every one the pilot tries)
  std::vector<IntegratorKind> only;
};

// For every vehicle kind the scene holds, one option that swaps that model
// in all the vehicles that have it:
//  - the report's car and the lone wheel on rim points (rim springs), and
//    the deformable tyre: the continuous wheel (exact circle contact) on a
//    bearing of the scenario's bearing stiffness and damping, the rim's
//    points kept for inertia only;
//  - a road car's tyres: the Magic Formula for the rigid stick-slip contact
//    and back (the cheaper of the two is the one the pilot finds cheaper:
//    their work per evaluation is the same, their stable steps are not).
// Empty when every vehicle already has the cheapest model it can have.
// `regularized_friction`: also the ground's friction as regularized Coulomb.
std::vector<ModelOption> modelOptions(const scenario::Scenario& s, bool regularized_friction = true);

// Work units (scenario/budget.hpp) of one force evaluation of s's model:
// what makes evaluations of two models comparable.
double workPerEvaluation(const scenario::Scenario& s);

}  // namespace groundsim::accuracy
