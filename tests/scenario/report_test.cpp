// Error reports stay short and printable whatever the input: the first 20
// problems then "and N more", user strings quoted, escaped and cut to 200
// characters, numbers in %g.
#include <gtest/gtest.h>

#include <cfloat>
#include <string>

#include "scenario/object_reader.hpp"
#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

TEST(Report, ListsTwentyProblemsThenCountsTheRest) {
  auto d = minimalDoc();
  for (int i = 0; i < 1000; ++i) d["vehicle"]["unknown_" + std::to_string(i)] = 1;
  const auto e = errorOf(d);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->issues().size(), kMaxListedIssues);
  EXPECT_EQ(e->omitted(), 1000u - kMaxListedIssues);
  const std::string what = e->what();
  EXPECT_NE(what.find("\nand 980 more problems"), std::string::npos) << what.substr(what.size() - 100);
  EXPECT_LT(what.size(), 4000u);
}

TEST(Report, QuoteEscapesAndCuts) {
  EXPECT_EQ(quote("a\"b\\c"), R"("a\"b\\c")");
  EXPECT_EQ(quote(std::string("x\0y\n", 4) + "\x7f"), R"("x\x00y\n\x7f")");
  const std::string q = quote(std::string(1000000, 'n'));
  EXPECT_LT(q.size(), kMaxQuotedChars + 40);
  EXPECT_NE(q.find("... (1000000 bytes)"), std::string::npos) << q;
  // never cut inside a UTF-8 sequence: 199 ASCII then a 2-byte letter
  const std::string u = quote(std::string(199, 'a') + "\xc3\xa9" + "zz");
  EXPECT_EQ(u.find("\xc3\"") , std::string::npos);
  EXPECT_EQ(u.substr(1, 200), std::string(199, 'a') + ".");
}

TEST(Report, LongNameIsQuotedEscapedAndCut) {
  auto d = minimalDoc();
  d["vehicle"]["name"] = std::string("\0\a", 2) + std::string(1 << 20, 'n');
  const auto issues = issuesOf(d);
  ASSERT_TRUE(hasIssue(issues, "/vehicle/name", "got \"\\x00\\x07nnn"));
  for (const Issue& i : issues) {
    EXPECT_LT(i.str().size(), 400u);
    for (char c : i.str()) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20) << "raw control character";
  }
}

TEST(Report, LongUnknownKeyIsCutInThePath) {
  auto d = minimalDoc();
  d["vehicle"][std::string(1 << 20, 'k') + std::string("\n", 1)] = 1;
  const auto issues = issuesOf(d);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_LT(issues[0].path.size(), 300u);
  EXPECT_EQ(issues[0].path.rfind("/vehicle/kkkk", 0), 0u);
  EXPECT_NE(issues[0].message.find("unknown key"), std::string::npos);
}

TEST(Report, NumbersArePrintedInShortForm) {
  EXPECT_EQ(formatNumber(DBL_MAX), "1.79769e+308");
  EXPECT_EQ(formatNumber(-1), "-1");
  EXPECT_EQ(formatNumber(5e-5), "5e-05");
  auto d = minimalDoc();
  d["vehicle"]["body_mass"] = DBL_MAX;
  EXPECT_TRUE(hasIssue(issuesOf(d), "/vehicle/body_mass", "got 1.79769e+308"));
}

TEST(Report, LongExpressionIsQuotedCutInItsError) {
  auto d = minimalDoc();
  d["ground"] = {{"type", "expression"}, {"expression", "z - w" + std::string(3000, ' ')}};
  const auto issues = issuesOf(d);
  ASSERT_FALSE(issues.empty());
  EXPECT_LT(issues[0].str().size(), 1300u) << issues[0].str().size();
}

}  // namespace
}  // namespace groundsim::scenario::test
