// Limits on JSON text and trees, checked without recursion. nlohmann's
// parser is iterative but copying or dumping a tree recurses once per
// level, so a document 10^5 levels deep must be refused before its tree
// exists: scanText() runs nlohmann's SAX parser over the text (no tree)
// and checks size, depth, value count and duplicate keys; checkTree() does
// the same walk for a tree built elsewhere (overrides, callers' documents).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "scenario/budget.hpp"
#include "scenario/scenario_error.hpp"

namespace groundsim::scenario {

// Records every problem of the text in `issues` (malformed JSON too); the
// text may be given to nlohmann::json::parse when nothing was recorded.
void scanText(const std::string& text, const Budget& budget, IssueList& issues);
// Depth and value count of an existing tree, iteratively.
void checkTree(const nlohmann::json& doc, const Budget& budget, IssueList& issues);

}  // namespace groundsim::scenario
