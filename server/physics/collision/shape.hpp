// Collision shapes as implicit functions (signed distance, < 0 inside) in
// their own frame, so a shape is a "ground" that moves with its body: the
// contact law of the report's eq. (10) applies to any point inside it.
// Boxes may be rounded; cylinders, capsules and cones stand on their local z
// axis, centred at the origin.
#pragma once

#include <vector>

#include "physics/base/math.hpp"

namespace groundsim {

enum class ShapeKind { Box, Sphere, Cylinder, Capsule, Cone };

struct Shape {
  ShapeKind kind = ShapeKind::Box;
  Vec3 half = Vec3::Constant(0.5);  // m  box: half extents (rounding included)
  double radius = 0.5;              // m  sphere, cylinder, capsule; cone: bottom radius; box: rounding
  double half_height = 0.5;         // m  cylinder, capsule (its straight part), cone
  double top_radius = 0.0;          // m  cone: radius at +half_height (0: a pointed cone)

  // Signed distance of p (shape frame): exact for these kinds, < 0 inside.
  double distance(const Vec3& p) const;
  // Outward unit normal at p: the distance's gradient (a box's in closed
  // form; the round kinds' by central differences, a step of 1e-6 of the
  // shape's size; a point at the exact centre of a symmetric shape takes +z).
  Vec3 normal(const Vec3& p) const;
  // Radius of the smallest origin-centred sphere holding the shape.
  double bound() const;
  // Half extents of the shape's axis-aligned box in its own frame.
  Vec3 extents() const;
  double volume() const;
  // Mass properties of the solid of uniform density and total mass `mass`:
  // centre of mass (shape frame) and inertia about it. Closed forms for
  // box (sharp corners), sphere, cylinder and cone; the capsule and rounded
  // boxes by their parts.
  void massProperties(double mass, Vec3* com, Mat3* inertia) const;
  // Points on the surface that probe other shapes and the ground: corners
  // and edge samples no farther apart than `spacing`, rims of round kinds.
  std::vector<Vec3> probes(double spacing) const;
};

}  // namespace groundsim
