// The validated `ground` section: which implicit surface, with what
// parameters. Kept as plain data (not a GroundPtr) because an expression
// ground holds a mutable parser: every Scene built from one Scenario gets
// its own ground instance (makeGround), so scenes may run on different
// threads.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "physics/ground/ground.hpp"
#include "physics/ground/heightfield.hpp"
#include "physics/base/math.hpp"
#include "physics/ground/surface_friction.hpp"

namespace groundsim::scenario {

enum class GroundKind { Plane, Incline, Cosine, Parabola, Cone, Bumps, Expression, Heightfield };

struct GroundSpec {
  GroundKind kind = GroundKind::Plane;
  Vec3 normal = Vec3::UnitZ();      // plane: unit normal (normalised when built)
  double offset = 0.0;              // m      plane: n . p = offset
  double angle_deg = 0.0;           // deg    incline
  Vec3 downhill = Vec3::UnitX();    // -      incline: horizontal direction it descends
  double amplitude = 0.5;           // m      cosine, bumps
  double wavelength = 0.0;          // m      cosine
  double wavelength_x = 0.0;        // m      bumps
  double wavelength_y = 0.0;        // m      bumps
  double curvature = 0.0;           // 1/m    parabola
  double slope = 0.0;               // -      cone
  std::string expression;           //        expression: H(x, y, z)
  double gradient_bound = std::numeric_limits<double>::infinity();  // expression
  // heightfield: loaded and prefiltered once at validation; immutable, so
  // every scene shares it (heightfield_section.cpp)
  std::shared_ptr<const HeightfieldGround> heightfield;
  // any kind: mu by place (friction_section.cpp)
  std::vector<FrictionPatch> friction_patches;
  std::shared_ptr<const FrictionGrid> friction_map;
};

const char* groundKindName(GroundKind k);
// A fresh ground for one scene (throws what the factories throw; a spec
// produced by validation never does).
GroundPtr makeGround(const GroundSpec& spec);
// The surface alone, without the friction patches and map.
GroundPtr makeShape(const GroundSpec& spec);

}  // namespace groundsim::scenario
