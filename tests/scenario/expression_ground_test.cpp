// Expression grounds: what is rejected, where, and why.
#include <gtest/gtest.h>

#include "scenario/expression_ground.hpp"
#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

std::vector<Issue> expressionIssues(const std::string& text, std::optional<double> bound = std::nullopt) {
  auto d = minimalDoc();
  d["ground"] = {{"type", "expression"}, {"expression", text}};
  if (bound) d["ground"]["gradient_bound"] = *bound;
  return issuesOf(d);
}

TEST(ExpressionGround, SyntaxErrorNamesThePositionAndReason) {
  const std::string text = "z - 0.5*cos(x";
  try {
    ExpressionGround g(text);
    FAIL() << "accepted";
  } catch (const ExpressionError& e) {
    EXPECT_GE(e.position(), static_cast<int>(text.find("cos")));  // at or after the unclosed call
    EXPECT_NE(std::string(e.reason()).find("arenthes"), std::string::npos) << e.reason();
  }
  const auto issues = expressionIssues(text);
  EXPECT_TRUE(hasIssue(issues, "/ground/expression", "at position "));
  EXPECT_TRUE(hasIssue(issues, "/ground/expression", text));
}

TEST(ExpressionGround, UnknownVariableIsNamedWithItsPosition) {
  const std::string text = "z - 0.5*cos(w)";
  try {
    ExpressionGround g(text);
    FAIL() << "accepted";
  } catch (const ExpressionError& e) {
    EXPECT_EQ(e.position(), static_cast<int>(text.find('w')));
    EXPECT_NE(e.reason().find("unknown variable"), std::string::npos) << e.reason();
    EXPECT_NE(e.reason().find("\"w\""), std::string::npos) << e.reason();
  }
  EXPECT_TRUE(hasIssue(expressionIssues(text), "/ground/expression",
                       "at position " + std::to_string(text.find('w'))));
}

TEST(ExpressionGround, NonFiniteAtTheOriginIsRejected) {
  EXPECT_TRUE(hasIssue(expressionIssues("z - sqrt(x - 1)"), "/ground/expression", "origin"));
  EXPECT_TRUE(hasIssue(expressionIssues("log(z)"), "/ground/expression", "origin"));
  EXPECT_TRUE(hasIssue(expressionIssues(""), "/ground/expression"));
}

TEST(ExpressionGround, PiIsDefinedAndEvaluationIsRepeatable) {
  const ExpressionGround g("z - cos(2*pi*x/8)");
  Vec3 grad;
  const double a = g.eval(Vec3(2.0, 0.0, 0.0), &grad);
  EXPECT_NEAR(a, 0.0, 1e-15);  // cos(pi/2)
  g.eval(Vec3(-3.0, 4.0, 5.0), &grad);
  EXPECT_EQ(g.eval(Vec3(2.0, 0.0, 0.0), &grad), a);  // no state carried between calls
}

TEST(ExpressionGround, GradientBoundIsKeptAndChecked) {
  // |grad (z - 0.5 cos x)| = sqrt(1 + 0.25 sin^2 x) <= 1.1181
  EXPECT_EQ(ExpressionGround("z - 0.5*cos(x)", 1.2).gradientBound(), 1.2);
  EXPECT_TRUE(std::isinf(ExpressionGround("z - 0.5*cos(x)").gradientBound()));
  EXPECT_TRUE(hasIssue(expressionIssues("z - 0.5*cos(x)", 1.05), "/ground/gradient_bound", "|grad H|"));
  auto d = minimalDoc();
  d["ground"] = {{"type", "expression"}, {"expression", "z - 0.5*cos(x)"}, {"gradient_bound", 1.2}};
  EXPECT_NO_THROW(parseScenario(d));
}

}  // namespace
}  // namespace groundsim::scenario::test

namespace groundsim::scenario::test {
namespace {

TEST(ExpressionGround, BatchHeightsEqualPointwiseValues) {
  const ExpressionGround g("z - 0.3*sin(x)*cos(y)");
  const double x[] = {0.0, 1.0, -2.5, 7.0}, y[] = {0.5, -1.0, 3.0, 0.0}, z[] = {0.1, -0.2, 0.0, 2.0};
  double H[4] = {-1, -1, -1, -1};
  g.heights(x, y, z, 1, 4, H);
  EXPECT_EQ(H[0], -1.0);  // outside [begin, end): untouched
  Vec3 grad;
  for (int k = 1; k < 4; ++k) EXPECT_EQ(H[k], g.eval(Vec3(x[k], y[k], z[k]), &grad)) << k;
}

}  // namespace
}  // namespace groundsim::scenario::test
