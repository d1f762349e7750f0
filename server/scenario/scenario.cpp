// Top level of a scenario document: load, parse, validate section by section.
#include "scenario/scenario.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "scenario/object_reader.hpp"
#include "scenario/presets.hpp"
#include "scenario/scenario_error.hpp"
#include "scenario/sections.hpp"

namespace groundsim::scenario {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw ScenarioError({Issue{path, message}});
}

void readVehicles(ObjectReader& top, nlohmann::json& doc, IssueList& issues, Scenario& s) {
  const bool one = top.has("vehicle"), many = top.has("vehicles");
  top.allow("vehicle");
  top.allow("vehicles");
  if (one && many) {
    issues.add("/vehicles", "give either \"vehicle\" (one object) or \"vehicles\" (an array), not both");
    return;
  }
  if (!one && !many) {
    issues.add("/vehicle", "missing required key (or give \"vehicles\", an array of vehicles)");
    return;
  }
  if (one) {
    s.vehicles.push_back(readVehicle(ObjectReader(doc["vehicle"], "/vehicle", issues)));
    return;
  }
  nlohmann::json& arr = doc["vehicles"];
  if (!arr.is_array()) {
    issues.add("/vehicles", "expected an array, got " + jsonTypeName(arr));
    return;
  }
  if (arr.empty()) {
    issues.add("/vehicles", "must hold at least one vehicle");
    return;
  }
  std::set<std::string> names;
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string path = "/vehicles/" + std::to_string(i);
    // with several vehicles the default name would repeat: ask for one
    if (arr[i].is_object() && !arr[i].contains("name"))
      issues.add(path + "/name", "missing required key (each of several vehicles needs a unique name)");
    VehicleSpec v = readVehicle(ObjectReader(arr[i], path, issues));
    if (arr[i].is_object() && arr[i].contains("name") && !names.insert(v.name).second)
      issues.add(path + "/name", "duplicate vehicle name \"" + v.name + "\"");
    s.vehicles.push_back(std::move(v));
  }
}

}  // namespace

nlohmann::json parseScenarioDocument(const std::string& json_text) {
  if (json_text.find_first_not_of(" \t\r\n") == std::string::npos) fail("", "empty document (expected a JSON object)");
  try {
    return nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::parse_error& e) {
    // nlohmann's what() starts with "[json.exception.parse_error.101] "
    std::string why = e.what();
    if (const auto p = why.find("] "); why.rfind("[json.exception", 0) == 0 && p != std::string::npos)
      why = why.substr(p + 2);
    fail("", "malformed JSON at byte " + std::to_string(e.byte) + ": " + why);
  } catch (const nlohmann::json::exception& e) {
    // e.g. out_of_range.406 "number overflow parsing '1e999'": the number
    // is not representable, so it cannot be validated either
    std::string why = e.what();
    if (const auto p = why.find("] "); p != std::string::npos) why = why.substr(p + 2);
    fail("", "invalid JSON: " + why);
  }
}

Scenario parseScenario(const std::string& json_text) { return parseScenario(parseScenarioDocument(json_text)); }

Scenario parseScenario(const nlohmann::json& input) { return parseScenario(input, FileAccess::none()); }

Scenario parseScenario(const nlohmann::json& input, const FileAccess& files) {
  Scenario s;
  s.document = input;
  nlohmann::json& doc = s.document;
  applyPreset(doc);  // its settings become ordinary keys, validated like any other
  IssueList issues;
  ObjectReader top(doc, "", issues);
  if (!top.valid()) issues.throwIfAny();

  s.name = top.string("name", "scenario");
  s.description = top.string("description", "");
  if (top.has("preset")) s.preset = top.choice("preset", "balanced", {"fast", "balanced", "accurate"});
  else top.allow("preset");  // optional: absent means the explicit settings below
  s.duration = top.number("duration", 5.0, Range::positive(1e6));
  s.output_rate = top.number("output_rate", 50.0, Range::positive(1e6));
  readPhysics(top.object("physics"), s.options);
  readContact(top.object("contact"), s.options.contact);
  // a frame more often than every step would repeat frames
  if (s.output_rate > 1.0 / s.options.dt * (1.0 + 1e-9))
    issues.add("/output_rate", "must be <= 1/physics.dt = " + formatNumber(1.0 / s.options.dt) + " Hz, got " +
                                   formatNumber(s.output_rate));
  if (!top.has("ground")) {
    top.allow("ground");
    issues.add("/ground", "missing required key (an object with \"type\")");
  } else {
    s.ground = readGround(top.object("ground"), files);
  }
  readVehicles(top, doc, issues, s);
  top.finish();
  issues.throwIfAny();
  return s;
}

nlohmann::json loadScenarioDocument(const std::string& path) {
  namespace fs = std::filesystem;
  const std::string quoted = "\"" + path + "\"";
  std::error_code ec;
  if (!fs::exists(path, ec)) fail("", quoted + ": no such file");
  if (fs::is_directory(path, ec)) fail("", quoted + ": is a directory, not a scenario file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("", quoted + ": cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail("", quoted + ": read error");
  const std::string s = text.str();
  if (s.find_first_not_of(" \t\r\n") == std::string::npos) fail("", quoted + ": file is empty");
  try {
    return parseScenarioDocument(s);
  } catch (const ScenarioError& e) {
    std::vector<Issue> named = e.issues();
    for (Issue& i : named) i.message = quoted + ": " + i.message;
    throw ScenarioError(std::move(named));
  }
}

Scenario loadScenarioFile(const std::string& path) {
  nlohmann::json doc = loadScenarioDocument(path);
  // an unnamed scenario is called after its file
  if (doc.is_object() && !doc.contains("name")) doc["name"] = std::filesystem::path(path).stem().string();
  return parseScenario(doc, FileAccess::local(std::filesystem::path(path).parent_path().string()));
}

}  // namespace groundsim::scenario
