#include "scenario/expression_ground.hpp"

#include <cctype>
#include <cmath>
#include <numbers>
#include <sstream>

#include <muParser.h>

namespace groundsim::scenario {

ExpressionError::ExpressionError(int position, const std::string& reason)
    : std::runtime_error(position >= 0 ? "at position " + std::to_string(position) + ": " + reason : reason),
      position_(position), reason_(reason) {}

namespace {

// Fourth-order central difference (-f(2h) + 8 f(h) - 8 f(-h) + f(-2h)) / 12h,
// muParser's Diff. Truncation error ~ h^4 |d5H| / 30 and rounding
// ~ 1.5 eps |H| / h balance at h ~ eps^(1/5) L ~ 7e-4 L for a ground whose
// features have length L. Grounds for vehicles vary on metre scales, so h
// is fixed at 2^-10 m (~1e-3): a power of two keeps p +- h exact (for
// |p| < 2^42 m) and the stencil symmetric. The step must not grow with |p|
// (Diff's default would scale it to 1e-7 |p|): a ripple far from the origin
// is as fine as one near it. Both errors are then ~1e-13 for metre-scale
// grounds; coordinates near 1e4 m add ~1e-9 from the rounding of x itself.
constexpr double kDiffStep = 0x1p-10;

// One parser with its own variables: the evaluation state of one simulation.
// muParser's bulk mode (Eval(results, n) over arrays) is not used: Debian
// builds muParser with OpenMP, so each bulk call forks a thread team, which
// for the 20-80 points of one body costs more than it saves and puts
// threads inside a step that other simulations share the machine with.
class ExpressionEvaluator final : public GroundEvaluator {
 public:
  explicit ExpressionEvaluator(const std::string& text) {
    // only x, y, z exist: muParser then rejects any other name as it parses
    // (no variable factory), which is the "unknown variable" check
    parser_.DefineVar("x", &x_);
    parser_.DefineVar("y", &y_);
    parser_.DefineVar("z", &z_);
    parser_.DefineConst("pi", std::numbers::pi);
    parser_.SetExpr(text);
    // muParser finishes parsing at the first Eval: do it now, not in a step
    x_ = y_ = z_ = 0.0;
    origin_ = parser_.Eval();
  }
  ExpressionEvaluator(const ExpressionEvaluator&) = delete;  // the parser points at our members
  ExpressionEvaluator& operator=(const ExpressionEvaluator&) = delete;

  double origin() const { return origin_; }

  double value(const Vec3& p) {
    x_ = p.x();
    y_ = p.y();
    z_ = p.z();
    return parser_.Eval();
  }

  double eval(const Vec3& p, Vec3* grad) override {
    const double H = value(p);
    if (grad) {
      // Diff moves one variable and puts it back
      *grad = Vec3(parser_.Diff(&x_, p.x(), kDiffStep), parser_.Diff(&y_, p.y(), kDiffStep),
                   parser_.Diff(&z_, p.z(), kDiffStep));
    }
    return H;
  }

  // The contact test needs H alone: one evaluation per point instead of the
  // 13 that eval() spends on the gradient.
  void heights(const double* x, const double* y, const double* z, int begin, int end, double* H) override {
    for (int k = begin; k < end; ++k) {
      x_ = x[k];
      y_ = y[k];
      z_ = z[k];
      H[k] = parser_.Eval();
    }
  }

 private:
  mu::Parser parser_;
  double x_ = 0.0, y_ = 0.0, z_ = 0.0, origin_ = 0.0;
};

}  // namespace

ExpressionGround::ExpressionGround(std::string expression, double gradient_bound)
    : text_(std::move(expression)), gradient_bound_(gradient_bound) {
  try {
    const ExpressionEvaluator check(text_);
    const double h0 = check.origin();
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

std::unique_ptr<GroundEvaluator> ExpressionGround::makeEvaluator() const {
  return std::make_unique<ExpressionEvaluator>(text_);
}

double ExpressionGround::value(const Vec3& p) const { return ExpressionEvaluator(text_).value(p); }

double ExpressionGround::eval(const Vec3& p, Vec3* grad) const { return ExpressionEvaluator(text_).eval(p, grad); }

void ExpressionGround::heights(const double* x, const double* y, const double* z, int begin, int end,
                               double* H) const {
  ExpressionEvaluator(text_).heights(x, y, z, begin, end, H);
}

std::string ExpressionGround::describe() const { return "expression H(x,y,z) = " + text_; }

std::optional<std::string> refuteGradientBound(const ExpressionGround& g, double bound) {
  // 41 x 41 x 9 points over [-20, 20]^2 x [-2, 2] m: where vehicles start
  GroundProbe probe(g);
  Vec3 grad;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j)
      for (int k = -4; k <= 4; ++k) {
        const Vec3 p(i, j, 0.5 * k);
        probe.eval(p, &grad);
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
