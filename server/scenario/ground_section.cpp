#include <cmath>
#include <numbers>

#include "scenario/expression_ground.hpp"
#include "scenario/sections.hpp"
#include "scenario/terrain_sections.hpp"

namespace groundsim::scenario {
namespace {

const std::vector<std::string> kKinds = {"plane", "incline", "cosine", "parabola", "cone", "bumps", "expression", "heightfield"};

// Every parameter key of any kind: allowed wholesale when the kind itself is
// missing or wrong, so one bad `type` does not also flag each parameter.
const std::vector<std::string> kAllKeys = {"normal",     "offset",       "angle_deg",    "downhill",
                                           "amplitude",  "wavelength",   "wavelength_x", "wavelength_y",
                                           "curvature",  "slope",        "expression",   "gradient_bound"};

// Lengths of the ground's features: a wavelength far below a wheel makes the
// contact meaningless and one far above is a plane.
const Range kWavelength{1e-3, 1e6, false, false};

void readExpression(ObjectReader& r, GroundSpec& g, const Budget& budget) {
  auto text = r.requiredString("expression");
  if (text && text->size() > budget.max_expression_length) {
    r.issue("expression", std::to_string(text->size()) + " characters, at most " +
                              std::to_string(budget.max_expression_length) + " " + budget.flag("max-expression-length"));
    text.reset();
  }
  const bool has_bound = r.has("gradient_bound");
  if (has_bound) {
    if (auto b = r.requiredNumber("gradient_bound", Range::positive())) g.gradient_bound = *b;
  } else {
    r.allow("gradient_bound");  // optional, and absent means "no bound": nothing to fill in
  }
  if (!text) return;
  g.expression = *text;
  try {
    ExpressionGround ground(g.expression, g.gradient_bound);
    if (has_bound && std::isfinite(g.gradient_bound))
      if (auto why = refuteGradientBound(ground, g.gradient_bound)) r.issue("gradient_bound", *why);
  } catch (const ExpressionError& e) {
    r.issue("expression", std::string(e.what()) + " (in " + quote(g.expression) + ")");
  }
}

}  // namespace

const char* groundKindName(GroundKind k) {
  return kKinds.at(static_cast<size_t>(k)).c_str();
}

GroundSpec readGround(ObjectReader r, const Budget& budget, const FileAccess& files) {
  GroundSpec g;
  const auto type = r.requiredChoice("type", kKinds);
  if (!type) {
    for (const std::string& k : kAllKeys) r.allow(k);
    for (const std::string& k : kHeightfieldKeys) r.allow(k);
    for (const std::string& k : kFrictionKeys) r.allow(k);
    r.finish();
    return g;
  }
  g.kind = static_cast<GroundKind>(std::find(kKinds.begin(), kKinds.end(), *type) - kKinds.begin());
  switch (g.kind) {
    case GroundKind::Plane: {
      g.normal = r.vec3("normal", Vec3::UnitZ());
      if (!(g.normal.norm() > 1e-9)) r.issue("normal", "must not be the zero vector");
      else if (g.normal.normalized().z() <= 0.0) r.issue("normal", "must point up (positive z): H > 0 is above ground");
      g.offset = r.number("offset", 0.0);
      break;
    }
    case GroundKind::Incline: {
      // 80 degrees: steeper than any tyre grips, and the car builder needs a
      // surface point below the car
      if (auto a = r.requiredNumber("angle_deg", Range::closed(-80.0, 80.0))) g.angle_deg = *a;
      const Eigen::VectorXd d = r.vector("downhill", Eigen::Vector2d(1.0, 0.0));
      g.downhill = Vec3(d[0], d[1], 0.0);
      if (!(g.downhill.norm() > 1e-9)) r.issue("downhill", "must not be the zero vector");
      break;
    }
    case GroundKind::Cosine:
      g.amplitude = r.number("amplitude", 0.5, Range::nonNegative(1e3));
      g.wavelength = r.number("wavelength", 2.0 * std::numbers::pi, kWavelength);
      break;
    case GroundKind::Parabola:
      if (auto c = r.requiredNumber("curvature", Range::closed(-100.0, 100.0))) g.curvature = *c;
      break;
    case GroundKind::Cone:
      if (auto s = r.requiredNumber("slope", Range::closed(-10.0, 10.0))) g.slope = *s;
      break;
    case GroundKind::Bumps:
      if (auto a = r.requiredNumber("amplitude", Range::nonNegative(1e3))) g.amplitude = *a;
      if (auto w = r.requiredNumber("wavelength_x", kWavelength)) g.wavelength_x = *w;
      if (auto w = r.requiredNumber("wavelength_y", kWavelength)) g.wavelength_y = *w;
      break;
    case GroundKind::Expression:
      readExpression(r, g, budget);
      break;
    case GroundKind::Heightfield:
      readHeightfield(r, g, files);
      break;
  }
  readSurfaceFriction(r, g, files);
  r.finish();
  return g;
}

GroundPtr makeGround(const GroundSpec& g) { return withSurfaceFriction(makeShape(g), g.friction_patches, g.friction_map); }

GroundPtr makeShape(const GroundSpec& g) {
  switch (g.kind) {
    case GroundKind::Plane: return makePlane(g.normal.normalized(), g.offset);
    case GroundKind::Incline: return makeIncline(g.angle_deg * std::numbers::pi / 180.0, g.downhill);
    case GroundKind::Cosine: return makeCosineWave(g.amplitude, g.wavelength);
    case GroundKind::Parabola: return makeParabola(g.curvature);
    case GroundKind::Cone: return makeCone(g.slope);
    case GroundKind::Bumps: return makeSinSinBumps(g.amplitude, g.wavelength_x, g.wavelength_y);
    case GroundKind::Expression: return std::make_shared<ExpressionGround>(g.expression, g.gradient_bound);
    case GroundKind::Heightfield: return g.heightfield;
  }
  return nullptr;
}

}  // namespace groundsim::scenario
