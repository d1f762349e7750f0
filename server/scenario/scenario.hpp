// Scenario layer: JSON text -> validated Scenario -> Scene (model + initial
// state). All validation happens here, once, at load; every problem is
// reported with its JSON pointer path and the reason, e.g.
//   /vehicle/wheel_radius: must be > 0, got -1
// Unknown keys are errors. The physics core never sees JSON.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "physics/model.hpp"
#include "physics/model_builder.hpp"
#include "physics/simulator.hpp"
#include "physics/state.hpp"
#include "physics/vehicle.hpp"
#include "scenario/ground_spec.hpp"
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

class ScenarioError : public std::runtime_error {
 public:
  explicit ScenarioError(std::vector<Issue> issues);
  const std::vector<Issue>& issues() const { return issues_; }

 private:
  std::vector<Issue> issues_;
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
};

// Parses and validates; throws ScenarioError listing every problem found.
Scenario parseScenario(const std::string& json_text);
Scenario parseScenario(const nlohmann::json& doc);
// Reads a file; a missing, empty or unreadable file is a ScenarioError too.
Scenario loadScenarioFile(const std::string& path);
// Reads and parses a file's JSON without validating it (for overrides
// before validation); the same file errors as loadScenarioFile.
nlohmann::json loadScenarioDocument(const std::string& path);
// Parses JSON text; malformed text is a ScenarioError at path "" naming
// the byte position and the reason.
nlohmann::json parseScenarioDocument(const std::string& json_text);

// Applies "a.b.c=value" to a document before validation (value parsed as
// JSON when it is valid JSON, else taken as a string). Throws ScenarioError
// naming the key when the path cannot be set.
void applyOverride(nlohmann::json& doc, const std::string& assignment);

// A road car's scripted controls: row i holds from rows[i].t on.
struct ControlTable {
  int road_car = 0;               // index among the model's road cars
  std::vector<TimedControls> rows;
};

struct Scene {
  BuiltModel built;               // model and initial state (controls set)
  std::vector<ControlTable> control_tables;  // one per road car
  std::vector<CarHandle> cars;    // one per vehicle, in document order
  std::vector<std::string> vehicle_names;
  double duration = 5.0;          // s
  double output_rate = 50.0;      // Hz
  // settings that run but sit near or beyond a known stability limit,
  // each naming the setting and the limit (physics/stability.hpp)
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
