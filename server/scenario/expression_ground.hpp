// A ground given as text, H(x, y, z) = 0, evaluated with muParser.
//
// The text is parsed once, at construction; eval() only runs muParser's
// bytecode. The gradient comes from fourth-order central differences (see
// expression_ground.cpp for the step choice), accurate to about 1e-12
// relative for smooth H varying on metre scales, far below what the
// contact force can notice.
//
// eval() is const but writes the parser's variables: like every Ground, one
// instance serves one model, stepped by one thread at a time.
#pragma once

#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <muParser.h>

#include "physics/ground.hpp"

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
  ExpressionGround(const ExpressionGround&) = delete;  // the parser points at our members
  ExpressionGround& operator=(const ExpressionGround&) = delete;

  double eval(const Vec3& p, Vec3* grad) const override;
  // The contact test needs H alone: one evaluation per point instead of the
  // 13 that eval() spends on the gradient.
  void heights(const double* x, const double* y, const double* z, int begin, int end,
               double* H) const override;
  double value(const Vec3& p) const;
  double gradientBound() const override { return gradient_bound_; }
  std::string describe() const override;
  const std::string& expression() const { return text_; }

 private:
  double partial(const Vec3& p, int axis) const;

  std::string text_;
  double gradient_bound_;
  mutable mu::Parser parser_;
  mutable double x_ = 0.0, y_ = 0.0, z_ = 0.0;
};

// A wrong gradient bound lets the broad phase skip real contacts, so the
// user's claim is spot-checked on a grid around the origin: returns the
// reason when |grad H| exceeds bound somewhere on it (a grid can refute a
// bound, never prove one).
std::optional<std::string> refuteGradientBound(const ExpressionGround& g, double bound);

}  // namespace groundsim::scenario
