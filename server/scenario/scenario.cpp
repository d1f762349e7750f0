// Top level of a scenario document: load, parse, validate section by section.
#include "scenario/scenario.hpp"

#include <cctype>
#include <filesystem>
#include <optional>
#include <fstream>
#include <set>
#include <sstream>

#include "scenario/json_limits.hpp"
#include "scenario/object_reader.hpp"
#include "scenario/presets.hpp"
#include "scenario/scenario_error.hpp"
#include "scenario/sections.hpp"
#include "scenario/terrain_loader.hpp"

namespace groundsim::scenario {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw ScenarioError({Issue{path, message}});
}

void readVehicles(ObjectReader& top, nlohmann::json& doc, IssueList& issues, Scenario& s, const Budget& budget) {
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
  // before reading any: 50,000 vehicles are refused in one line, not
  // validated one by one and then built
  if (arr.size() > static_cast<size_t>(budget.max_vehicles)) {
    issues.add("/vehicles", std::to_string(arr.size()) + " vehicles, at most " + std::to_string(budget.max_vehicles) +
                                " " + budget.flag("max-vehicles"));
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
      issues.add(path + "/name", "duplicate vehicle name " + quote(v.name));
    s.vehicles.push_back(std::move(v));
  }
}

// Why a free text cannot be shown as it is, or nullopt.
std::optional<std::string> badText(const std::string& text, size_t most) {
  if (text.size() > most)
    return std::to_string(text.size()) + " characters, at most " + std::to_string(most) + ", got " + quote(text);
  for (unsigned char c : text)
    if (c < 0x20 || c == 0x7f) return "must not contain control characters, got " + quote(text);
  return std::nullopt;
}

// The race's grid places vehicle k at slot k (x, y, heading), on the ground.
void placeOnGrid(const RaceSpec& race, std::vector<VehicleSpec>& vehicles) {
  for (std::size_t k = 0; k < vehicles.size() && k < race.grid.size(); ++k) {
    CarPlacement& p = vehicles[k].placement;
    p.position.x() = race.grid[k].position[0];
    p.position.y() = race.grid[k].position[1];
    p.yaw = race.grid[k].yaw;
  }
}

// The bots' policy file, read as a heightfield is (a client collecting the
// files to send only notes its name); what it holds is checked where it is
// used (drivers/policy.hpp), when a session gives it the wheel.
void readBotPolicy(RaceSpec& race, const FileAccess& files, IssueList& issues) {
  if (race.bot_policy.empty()) return;
  if (files.mode == FileAccess::Mode::Collect) {
    if (files.collected) files.collected->push_back(race.bot_policy);
    return;
  }
  try {
    race.bot_policy_text = std::make_shared<const std::string>(loadFileBytes(files, race.bot_policy, kMaxBotPolicyBytes));
  } catch (const TerrainError& e) {
    issues.add("/race/bot_policy", e.what());
  }
}

// A task that reads a race track needs one: a line to follow (the track's
// centre line, or 2 gates or more) and, to tell off track, its width.
void checkTaskTrack(const TaskSpec& t, const std::optional<RaceSpec>& race, IssueList& issues) {
  if (!t.usesTrack()) return;
  if (!race || (race->centerline.size() < 2 && race->gates.size() < 2)) {
    issues.add("/task", "its track features, track rewards or track terminations need a race section with a track "
                        "(race.track.centerline) or at least 2 gates");
    return;
  }
  const bool width = t.reward.off_track != 0.0 || t.off_track_end > 0.0;
  if (width && race->centerline.empty())
    issues.add(t.off_track_end > 0.0 ? "/task/termination/off_track" : "/task/reward/off_track",
               "needs the track's width: the race section has no track (race.track.half_width)");
}

}  // namespace

std::optional<RaceSpec> readRaceSection(const nlohmann::json& document) {
  if (!document.is_object() || !document.contains("race")) return std::nullopt;
  nlohmann::json copy = document["race"];
  int vehicles = 1;
  if (document.contains("vehicles") && document["vehicles"].is_array())
    vehicles = static_cast<int>(document["vehicles"].size());
  IssueList issues;
  RaceSpec r = readRace(ObjectReader(copy, "/race", issues), vehicles);
  issues.throwIfAny();
  return r;
}

nlohmann::json parseScenarioDocument(const std::string& json_text, const Budget& budget) {
  if (json_text.size() <= budget.max_document_bytes && json_text.find_first_not_of(" \t\r\n") == std::string::npos)
    fail("", "empty document (expected a JSON object)");
  IssueList issues;
  scanText(json_text, budget, issues);
  issues.throwIfAny();
  // the text is within every limit now, so the tree is too
  return nlohmann::json::parse(json_text);
}

namespace {

Scenario validate(Scenario s, const Budget& budget, const FileAccess& files);

}  // namespace

Scenario parseScenario(const std::string& json_text, const Budget& budget, const FileAccess& files) {
  return parseScenario(parseScenarioDocument(json_text, budget), budget, files);
}

Scenario parseScenario(const nlohmann::json& input, const Budget& budget, const FileAccess& files) {
  // a tree built elsewhere: checked before the (recursive) copy below
  IssueList limits;
  checkTree(input, budget, limits);
  limits.throwIfAny();
  Scenario s;
  s.document = input;
  return validate(std::move(s), budget, files);
}

Scenario parseScenario(nlohmann::json&& input, const Budget& budget, const FileAccess& files) {
  IssueList limits;
  checkTree(input, budget, limits);
  limits.throwIfAny();
  Scenario s;
  s.document = std::move(input);
  return validate(std::move(s), budget, files);
}

namespace {

Scenario validate(Scenario s, const Budget& budget, const FileAccess& files) {
  nlohmann::json& doc = s.document;
  applyPreset(doc);  // its settings become ordinary keys, validated like any other
  IssueList issues;
  ObjectReader top(doc, "", issues);
  if (!top.valid()) issues.throwIfAny();

  // both are printed and published as they are: bounded, no control characters
  s.name = top.string("name", "scenario");
  if (auto why = badText(s.name, 256)) top.issue("name", *why);
  s.description = top.string("description", "");
  if (auto why = badText(s.description, 4096)) top.issue("description", *why);
  if (top.has("preset")) s.preset = top.choice("preset", "balanced", {"fast", "balanced", "accurate"});
  else top.allow("preset");  // optional: absent means the explicit settings below
  s.duration = top.number("duration", 5.0, Range::positive(1e6));
  s.output_rate = top.number("output_rate", 50.0, Range::positive(1e6));
  readPhysics(top.object("physics"), s.options);
  readContact(top.object("contact"), s.options.contact);
  readCollisions(top.object("collisions"), s.options.collision);
  // a frame more often than every step would repeat frames
  if (s.output_rate > 1.0 / s.options.dt * (1.0 + 1e-9))
    issues.add("/output_rate", "must be <= 1/physics.dt = " + formatNumber(1.0 / s.options.dt) + " Hz, got " +
                                   formatNumber(s.output_rate));
  if (!top.has("ground")) {
    top.allow("ground");
    issues.add("/ground", "missing required key (an object with \"type\")");
  } else {
    s.ground = readGround(top.object("ground"), budget, files);
  }
  readVehicles(top, doc, issues, s, budget);
  s.objects = readObjects(top, s.vehicles);
  // written by clients that send the files with the scenario (assets.hpp);
  // the files themselves are read through `files`
  top.allow("assets");
  s.assets = readAssetManifest(doc, issues);
  // the task reads the vehicles' names and kinds: only once they are valid
  if (top.has("task") && issues.empty()) s.task = readTask(top.object("task"), s.vehicles);
  else top.allow("task");
  if (top.has("accuracy")) s.accuracy = readAccuracy(top.object("accuracy"));
  if (top.has("race")) {
    s.race = readRace(top.object("race"), static_cast<int>(s.vehicles.size()));
    placeOnGrid(*s.race, s.vehicles);
    readBotPolicy(*s.race, files, issues);
  } else {
    top.allow("race");
  }
  if (s.task) checkTaskTrack(*s.task, s.race, issues);
  top.finish();
  issues.throwIfAny();
  checkBudget(s, budget);
  return s;
}

}  // namespace

nlohmann::json loadScenarioDocument(const std::string& path, const Budget& budget) {
  namespace fs = std::filesystem;
  const std::string name = quote(path);
  std::error_code ec;
  if (!fs::exists(path, ec)) fail("", name + ": no such file");
  if (fs::is_directory(path, ec)) fail("", name + ": is a directory, not a scenario file");
  // refused before reading: a 50 MB file is not read into memory to be refused
  if (const auto size = fs::file_size(path, ec); !ec && size > budget.max_document_bytes)
    fail("", name + ": file of " + std::to_string(size) + " bytes, at most " +
                 std::to_string(budget.max_document_bytes) + " " + budget.flag("max-document-bytes"));
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("", name + ": cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) fail("", name + ": read error");
  const std::string s = text.str();
  if (s.find_first_not_of(" \t\r\n") == std::string::npos) fail("", name + ": file is empty");
  try {
    return parseScenarioDocument(s, budget);
  } catch (const ScenarioError& e) {
    std::vector<Issue> named = e.issues();
    for (Issue& i : named)
      if (i.path.empty()) i.message = name + ": " + i.message;
    throw ScenarioError(std::move(named), e.omitted());
  }
}

Scenario loadScenarioFile(const std::string& path, const Budget& budget) {
  nlohmann::json doc = loadScenarioDocument(path, budget);
  // an unnamed scenario is called after its file
  if (doc.is_object() && !doc.contains("name")) doc["name"] = std::filesystem::path(path).stem().string();
  return parseScenario(std::move(doc), budget, FileAccess::local(std::filesystem::path(path).parent_path().string()));
}

}  // namespace groundsim::scenario
