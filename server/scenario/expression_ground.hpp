// A ground given as text, H(x, y, z) = 0, evaluated with muParser.
//
// The text is checked at construction (it parses, names only x, y, z, and
// is finite at the origin). The ground itself holds no parser: muParser
// evaluates through variables it points at, which is state, and one
// shared_ptr<const Model> may be stepped by several simulations on several
// threads. Each simulation's Workspace gets its own parser and variables
// from makeEvaluator(); the const eval()/heights() build a temporary one per
// call (thread-safe, slow: for one-off queries, not the force loop).
//
// The gradient is muParser's own Diff, a fourth-order central difference
// (see expression_ground.cpp for the step), accurate to about 1e-12
// relative for smooth H varying on metre scales, far below what the contact
// force can notice.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "physics/ground/ground.hpp"

namespace groundsim::scenario {

// Why an expression was rejected. position is muParser's 0-based character
// index, or -1 when the problem has no position (e.g. NaN at the origin).
class ExpressionError : public std::runtime_error {
 public:
  ExpressionError(int position, const std::string& reason);
  int position() const { return position_; }
  const std::string& reason() const { return reason_; }

 private:
  int position_;
  std::string reason_;
};

class ExpressionGround final : public Ground {
 public:
  // Throws ExpressionError for text that does not parse, uses variables
  // other than x, y, z, or is not finite at the origin. gradient_bound, when
  // finite, is the user's claim max |grad H| <= bound (enables the broad
  // phase); see refuteGradientBound.
  explicit ExpressionGround(std::string expression,
                            double gradient_bound = std::numeric_limits<double>::infinity());

  double eval(const Vec3& p, Vec3* grad) const override;
  void heights(const double* x, const double* y, const double* z, int begin, int end,
               double* H) const override;
  double value(const Vec3& p) const;
  double gradientBound() const override { return gradient_bound_; }
  std::string describe() const override;
  std::unique_ptr<GroundEvaluator> makeEvaluator() const override;
  const std::string& expression() const { return text_; }

 private:
  std::string text_;
  double gradient_bound_;
};

// A wrong gradient bound lets the broad phase skip real contacts, so the
// user's claim is spot-checked on a grid around the origin: returns the
// reason when |grad H| exceeds bound somewhere on it (a grid can refute a
// bound, never prove one).
std::optional<std::string> refuteGradientBound(const ExpressionGround& g, double bound);

}  // namespace groundsim::scenario
