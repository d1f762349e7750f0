// Building the collision part of a model: a group per vehicle (its shapes
// and probes derived from the vehicle's own parts) and per object, and the
// derived data build() fills in (ranges, masses, bounds).
#pragma once

#include <string>

#include <Eigen/Core>

#include "physics/core/model.hpp"
#include "physics/build/model_builder.hpp"

namespace groundsim {

// The collision group of vehicle `vehicle` (already added): colliders and
// probes from its parts, each kind its own way (docs/contact.md):
// - the report's car and its variants: a rounded box around the chassis'
//   points, a disc per wheel; probes: every simulated point (axle, rim,
//   tyre) and each circle wheel's deepest point;
// - a lone wheel: its disc, its rim points or circle;
// - a road car: its body box (`body_size`) and four wheel discs at the
//   hubs; probes: the box's corners and edge samples and three points per
//   tyre (bottom, front, back).
void addVehicleCollision(ModelBuilder& b, int vehicle);

// A road car's body box [length, width, height] (m): `body_size`, each zero
// entry derived (1.74 wheelbase, 1.16 track, 2.64 cg_height). Lengthwise it
// is centred on the axles' midpoint.
Vec3 roadCarBodySize(const RoadCarParams& p);

// An obstacle: mass 0 is static (a shape fixed in the world), else a rigid
// body of uniform density whose surface probes also touch the ground.
struct ObjectSpec {
  std::string name;
  Shape shape;
  Vec3 position = Vec3::Zero();     // m      shape centre
  Quat orientation = Quat::Identity();
  double mass = 0.0;                // kg     0: static
  double friction = 0.5;            // -      against bodies (the ground's friction applies on the ground)
  Vec3 velocity = Vec3::Zero();     // m/s
};
// Returns the object's body index, or -1 for a static object.
int addSceneObject(ModelBuilder& b, const ObjectSpec& o);

// Called by ModelBuilder::build() with the initial state: sorts colliders
// and probes by group, sets each group's ranges, mass, reference body and
// bound, and whether the step needs the broad phase at all.
void finishCollisionModel(Model& m, const Eigen::VectorXd& y);

}  // namespace groundsim
