#include "scenario/expression_ground.hpp"

#include <cctype>
#include <cmath>
#include <numbers>
#include <sstream>

namespace groundsim::scenario {

ExpressionError::ExpressionError(int position, const std::string& reason)
    : std::runtime_error(position >= 0 ? "at position " + std::to_string(position) + ": " + reason : reason),
      position_(position), reason_(reason) {}

ExpressionGround::ExpressionGround(std::string expression, double gradient_bound)
    : text_(std::move(expression)), gradient_bound_(gradient_bound) {
  try {
    // only x, y, z exist: muParser then rejects any other name as it parses
    // (no variable factory), which is the "unknown variable" check
    parser_.DefineVar("x", &x_);
    parser_.DefineVar("y", &y_);
    parser_.DefineVar("z", &z_);
    parser_.DefineConst("pi", std::numbers::pi);
    parser_.SetExpr(text_);
    // muParser finishes parsing at the first Eval: do it now, at load time
    x_ = y_ = z_ = 0.0;
    const double h0 = parser_.Eval();
    if (!std::isfinite(h0)) {
      std::ostringstream s;
      s << "evaluates to " << h0 << " at the origin (0, 0, 0); H must be finite everywhere the vehicle goes";
      throw ExpressionError(-1, s.str());
    }
  } catch (const mu::Parser::exception_type& e) {
    std::string reason = e.GetMsg();
    // muParser calls an undefined name an "unexpected token"; say what it is
    if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN && !e.GetToken().empty() &&
        (std::isalpha(static_cast<unsigned char>(e.GetToken()[0])) || e.GetToken()[0] == '_'))
      reason = "unknown variable or function \"" + e.GetToken() + "\" (variables are x, y, z) - " + reason;
    throw ExpressionError(e.GetPos(), reason);
  }
}

double ExpressionGround::value(const Vec3& p) const {
  x_ = p.x();
  y_ = p.y();
  z_ = p.z();
  return parser_.Eval();
}

// Fourth-order central difference (-f(2h) + 8 f(h) - 8 f(-h) + f(-2h)) / 12h.
// Truncation error ~ h^4 |d5H| / 30 and rounding ~ 1.5 eps |H| / h balance
// at h ~ eps^(1/5) L ~ 7e-4 L for a ground whose features have length L.
// Grounds for vehicles vary on metre scales, so h is fixed at 2^-10 m
// (~1e-3): a power of two keeps p +- h exact (for |p| < 2^42 m) and the
// stencil symmetric. The step must not grow with |p|: a ripple far from the
// origin is as fine as one near it (cos x at x = 1000 with h scaled to |x|
// would be off by 1e-3). Both errors are then ~1e-13 for metre-scale
// grounds; coordinates near 1e4 m add ~1e-9 from the rounding of x itself.
double ExpressionGround::partial(const Vec3& p, int axis) const {
  constexpr double h = 0x1p-10;
  const double c = p[axis];
  Vec3 q = p;
  auto at = [&](double offset) {
    q[axis] = c + offset;
    return value(q);
  };
  const double f2 = at(2 * h), f1 = at(h), m1 = at(-h), m2 = at(-2 * h);
  return (8.0 * (f1 - m1) - (f2 - m2)) / (12.0 * h);
}

double ExpressionGround::eval(const Vec3& p, Vec3* grad) const {
  if (grad) *grad = Vec3(partial(p, 0), partial(p, 1), partial(p, 2));
  return value(p);
}

void ExpressionGround::heights(const double* x, const double* y, const double* z, int begin, int end,
                               double* H) const {
  for (int k = begin; k < end; ++k) {
    x_ = x[k];
    y_ = y[k];
    z_ = z[k];
    H[k] = parser_.Eval();
  }
}

std::string ExpressionGround::describe() const { return "expression H(x,y,z) = " + text_; }

std::optional<std::string> refuteGradientBound(const ExpressionGround& g, double bound) {
  // 41 x 41 x 9 points over [-20, 20]^2 x [-2, 2] m: where vehicles start
  Vec3 grad;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j)
      for (int k = -4; k <= 4; ++k) {
        const Vec3 p(i, j, 0.5 * k);
        g.eval(p, &grad);
        const double n = grad.norm();
        if (std::isfinite(n) && n <= bound * (1.0 + 1e-9)) continue;
        std::ostringstream s;
        s.precision(6);
        s << "is " << bound << " but |grad H| = " << n << " at (" << p.x() << ", " << p.y() << ", "
          << p.z() << "); omit it or give a true upper bound";
        return s.str();
      }
  return std::nullopt;
}

}  // namespace groundsim::scenario
