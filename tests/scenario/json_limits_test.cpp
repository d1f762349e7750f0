// The text is checked before a tree exists: nesting depth, size, value
// count and duplicate keys are refused with their path, in bounded time and
// memory, and nothing recursive ever runs on a deep document.
#include <gtest/gtest.h>

#include <string>

#include "scenario_test_util.hpp"

namespace groundsim::scenario::test {
namespace {

const std::string kHead = R"({"ground": {"type": "plane"}, "vehicle": {}, )";

std::string repeat(const std::string& s, int n) {
  std::string out;
  out.reserve(s.size() * static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

// {"z":{"":{"": ... 1}}} 10^5 deep: overflowed the stack in the recursive
// copy of the document (SIGSEGV) before the pre-scan
TEST(JsonLimits, DeepObjectIsRefusedWithPathAndLimit) {
  const std::string text = kHead + "\"z\": " + repeat("{\"\":", 100000) + "1" + repeat("}", 100000) + "}";
  const auto issues = issuesOf(text);
  ASSERT_EQ(issues.size(), 1u) << listed(issues);
  EXPECT_EQ(issues[0].path.rfind("/z//", 0), 0u) << issues[0].path;
  EXPECT_NE(issues[0].message.find("deeper than 64 levels"), std::string::npos) << issues[0].message;
  EXPECT_NE(issues[0].message.find("(groundsim run --max-depth)"), std::string::npos);
}

TEST(JsonLimits, DeepArrayIsRefusedToo) {
  const std::string text = kHead + "\"z\": " + repeat("[", 100000) + repeat("]", 100000) + "}";
  EXPECT_TRUE(hasIssue(issuesOf(text), "/z/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0/0",
                       "deeper than 64"));
}

TEST(JsonLimits, DepthLimitIsTheBudgets) {
  // physics.limits is the third level (top object, physics, limits)
  const std::string text = kHead + "\"physics\": {\"limits\": {}}}";
  Budget b;
  b.max_depth = 2;
  EXPECT_TRUE(hasIssue(issuesOf(parseScenarioText(text, b)), "/physics/limits", "deeper than 2 levels"));
  b.max_depth = 3;
  EXPECT_NO_THROW(parseScenario(text, b));
}

TEST(JsonLimits, DeepTreeBuiltElsewhereIsRefusedBeforeCopying) {
  // a tree 10^5 deep made in memory (nlohmann's destructor is iterative)
  nlohmann::json doc = minimalDoc();
  nlohmann::json deep = 1;
  for (int i = 0; i < 100000; ++i) {
    nlohmann::json outer = nlohmann::json::object();
    outer[""] = std::move(deep);
    deep = std::move(outer);
  }
  doc["z"] = std::move(deep);
  EXPECT_TRUE(hasIssue(issuesOf(doc), "", "deeper than 64 levels"));
}

TEST(JsonLimits, DuplicateKeysAreRefusedAtAnyDepth) {
  // the last value used to win silently, hiding the invalid -1
  const std::string text = R"({"duration": -1, "duration": 1, "ground": {"type": "plane", "type": "cone"},
      "vehicles": [{"name": "a"}, {"name": "b", "initial": {"speed": 1, "speed": 2}}]})";
  const auto issues = issuesOf(text);
  EXPECT_TRUE(hasIssue(issues, "/duration", "duplicate key \"duration\""));
  EXPECT_TRUE(hasIssue(issues, "/ground/type", "duplicate key \"type\""));
  EXPECT_TRUE(hasIssue(issues, "/vehicles/1/initial/speed", "duplicate key \"speed\""));
  EXPECT_EQ(issues.size(), 3u) << listed(issues);
}

TEST(JsonLimits, SameKeyInDifferentObjectsIsFine) {
  EXPECT_NO_THROW(parseScenario(std::string(R"({"ground": {"type": "plane"},
      "vehicles": [{"name": "a", "initial": {"position": [0, 0, 0]}}, {"name": "b", "initial": {"position": [9, 0, 0]}}]})")));
}

TEST(JsonLimits, DocumentSizeIsRefusedBeforeParsing) {
  Budget b;
  b.max_document_bytes = 100;
  const std::string text = kHead + "\"description\": \"" + std::string(200, 'x') + "\"}";
  const auto issues = issuesOf(parseScenarioText(text, b));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_NE(issues[0].message.find("bytes, at most 100 (groundsim run --max-document-bytes)"), std::string::npos)
      << issues[0].message;
}

TEST(JsonLimits, ValueCountIsBounded) {
  Budget b;
  b.max_json_values = 1000;
  const std::string text = kHead + "\"z\": [" + repeat("0,", 2000) + "0]}";
  // values: top, ground, "plane", vehicle, z, then z's elements: the 1001st is z[995]
  EXPECT_TRUE(hasIssue(issuesOf(parseScenarioText(text, b)), "/z/995", "more than 1000 JSON values"));
}

TEST(JsonLimits, DeepOverrideValueIsRefused) {
  auto d = minimalDoc();
  try {
    applyOverride(d, "z=" + repeat("[", 10000) + repeat("]", 10000));
    ADD_FAILURE() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("deeper than 64"), std::string::npos) << e.what();
  }
}

TEST(JsonLimits, MalformedTextStillNamesTheByte) {
  EXPECT_TRUE(hasIssue(issuesOf(std::string(R"({"ground": )")), "", "malformed JSON at byte"));
  EXPECT_TRUE(hasIssue(issuesOf(std::string(R"({"duration": 1e999})")), "", "number overflow"));
}

}  // namespace
}  // namespace groundsim::scenario::test
