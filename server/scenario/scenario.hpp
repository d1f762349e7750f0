// Scenario layer: JSON text -> validated Scenario -> Scene (model + initial
// state). All validation happens here, once, at load; every problem is
// reported with its JSON pointer path and the reason, e.g.
//   /vehicle/wheel_radius: must be > 0, got -1
// Unknown keys are errors, and so are duplicate keys. Every limit of the
// model budget (budget.hpp) is checked during validation, before anything
// is built. Error reports are capped (kMaxListedIssues, then "and N more"),
// and user strings in them are quoted, escaped and cut (quote()). The
// physics core never sees JSON.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physics/core/model.hpp"
#include "physics/build/model_builder.hpp"
#include "physics/simulator.hpp"
#include "physics/core/state.hpp"
#include "physics/build/vehicle.hpp"
#include "scenario/budget.hpp"
#include "scenario/accuracy_spec.hpp"
#include "scenario/assets.hpp"
#include "scenario/file_access.hpp"
#include "scenario/ground_spec.hpp"
#include "scenario/object_spec.hpp"
#include "scenario/race_spec.hpp"
#include "scenario/task_spec.hpp"
#include "scenario/vehicle_spec.hpp"

namespace groundsim::scenario {

struct Issue {
  std::string path;     // JSON pointer, "" for the document itself
  std::string message;  // the reason
  std::string str() const {
    std::string s = path.empty() ? std::string("/") : path;
    s += ": ";
    s += message;
    return s;
  }
};

// A report lists at most this many problems, then "and N more".
inline constexpr std::size_t kMaxListedIssues = 20;
// User strings (names, keys, expressions, file names) in messages are cut
// to this many characters.
inline constexpr std::size_t kMaxQuotedChars = 200;

// `s` in double quotes, with quotes, backslashes and control characters
// escaped (\n, \t, \x00), cut to max_chars with "..." and its full length.
std::string quote(const std::string& s, std::size_t max_chars = kMaxQuotedChars);

class ScenarioError : public std::runtime_error {
 public:
  // `omitted`: problems found beyond those listed (see kMaxListedIssues).
  explicit ScenarioError(std::vector<Issue> issues, std::size_t omitted = 0);
  // At most kMaxListedIssues, in the order found.
  const std::vector<Issue>& issues() const { return issues_; }
  std::size_t omitted() const { return omitted_; }
  // Every listed issue, then "and N more problems" when some were omitted,
  // joined by `separator`; what() is lines("\n").
  std::string lines(const std::string& separator) const;

 private:
  ScenarioError(std::vector<Issue> capped, std::size_t omitted, int);
  std::vector<Issue> issues_;
  std::size_t omitted_ = 0;
};

// A validated scenario: the document with every default filled in, plus the
// typed values the builder needs.
struct Scenario {
  nlohmann::json document;        // complete, defaults filled: what was simulated
  std::string name;
  double duration = 5.0;          // s
  double output_rate = 50.0;      // Hz
  std::string description;
  std::string preset;             // "fast" | "balanced" | "accurate", "" when absent
  Options options;                // physics + contact
  GroundSpec ground;
  std::vector<VehicleSpec> vehicles;  // document order (`vehicle` is one)
  std::vector<ObjectEntry> objects;   // `objects`: obstacles, static or with mass
  std::optional<TaskSpec> task;   // the `task` section (experiments), when present
  std::vector<AssetRef> assets;   // the `assets` manifest (files sent with the scenario), when present
  std::optional<AccuracySpec> accuracy;  // the `accuracy` section, when present
  std::optional<RaceSpec> race;   // the `race` section, when present (its grid already placed the vehicles)
};

// The `race` section of a validated document (Scenario::document), read
// again without the rest (a session reads it from the document it keeps);
// nullopt when it has none. Throws ScenarioError as parseScenario would.
std::optional<RaceSpec> readRaceSection(const nlohmann::json& document);

// Parses and validates against the budget; throws ScenarioError listing
// the problems found (the first kMaxListedIssues). A Scenario returned is
// within the budget: buildScene(s) costs at most what the budget allows.
// Files it names (heightfields, friction maps) are read under `files`; by
// default none may be named.
Scenario parseScenario(const std::string& json_text, const Budget& budget = Budget{},
                       const FileAccess& files = FileAccess::none());
// The tree's nesting depth and size are checked (without recursion) before
// anything else.
Scenario parseScenario(const nlohmann::json& doc, const Budget& budget = Budget{},
                       const FileAccess& files = FileAccess::none());
// The same, taking the tree over instead of copying it (half the memory).
Scenario parseScenario(nlohmann::json&& doc, const Budget& budget = Budget{},
                       const FileAccess& files = FileAccess::none());
// The default budget, files read under `files`.
inline Scenario parseScenario(const nlohmann::json& doc, const FileAccess& files) {
  return parseScenario(doc, Budget{}, files);
}
// Reads a file; a missing, empty, unreadable or oversized file is a
// ScenarioError too. Files it names resolve against its directory
// (FileAccess::local).
Scenario loadScenarioFile(const std::string& path, const Budget& budget = Budget{});
// Reads and parses a file's JSON without validating it (for overrides
// before validation); the same file errors as loadScenarioFile.
nlohmann::json loadScenarioDocument(const std::string& path, const Budget& budget = Budget{});
// Parses JSON text. Before any tree is built, one streaming pass checks the
// size (max_document_bytes), nesting depth (max_depth), number of values
// (max_json_values) and duplicate keys (refused, each with its path), so no
// tree too deep for the recursive parts of nlohmann (copy, dump) is ever
// built. Malformed text is a ScenarioError at path "" naming the byte
// position and the reason.
nlohmann::json parseScenarioDocument(const std::string& json_text, const Budget& budget = Budget{});

// The counts the scene of a validated scenario will have, from its specs
// (no building): exact for points, particles, springs, bodies and state.
ModelSize estimateModelSize(const Scenario& s);
// Throws ScenarioError for every limit of the budget the scenario exceeds
// (parseScenario calls it; exposed for callers that change the budget).
void checkBudget(const Scenario& s, const Budget& budget);
// The run-length limits (max_steps, max_work) for a run of `duration`
// seconds of scenario s, e.g. a server session whose request overrides the
// scenario's duration; throws ScenarioError at "/duration". A duration <= 0
// or infinite (run until stopped) is not bounded here: pacing bounds it.
void checkRunLength(const Scenario& s, double duration, const Budget& budget);

// Applies "a.b.c=value" to a document before validation (value parsed as
// JSON when it is valid JSON, within the budget's depth and size, else
// taken as a string). Throws ScenarioError naming the key when the path
// cannot be set.
void applyOverride(nlohmann::json& doc, const std::string& assignment, const Budget& budget = Budget{});

// A road car's scripted controls: row i holds from rows[i].t on.
struct ControlTable {
  int road_car = 0;               // index among the model's road cars
  std::vector<TimedControls> rows;
};

// The row in force at simulated time t (the last with row.t <= t, with half a
// step of slack so a row at t = k dt applies to step k despite rounding), or
// nullptr before the first. Rows are sorted by t (validation), so this is a
// binary search: a table of many rows costs log(rows) per step.
const TimedControls* rowInForce(const ControlTable& table, double t, double dt);

struct Scene {
  BuiltModel built;               // model and initial state (controls set)
  std::vector<ControlTable> control_tables;  // one per road car
  std::vector<CarHandle> cars;    // one per vehicle, in document order
  std::vector<std::string> vehicle_names;
  double duration = 5.0;          // s
  double output_rate = 50.0;      // Hz
  // settings that run but sit near or beyond a known stability limit,
  // each naming the setting and the limit (physics/checks/stability.hpp)
  std::vector<std::string> warnings;
};

// Builds the physics model and initial state. Throws ScenarioError for
// problems only visible while building (e.g. no ground below a vehicle).
Scene buildScene(const Scenario& s);

// n steps of the scene, each starting with the road cars' controls of its
// table row at the step's start time (rows at t take effect on the first
// step starting at or after t). False once the run diverged.
bool stepScene(const Scene& scene, Simulator& sim, long long n);

}  // namespace groundsim::scenario
