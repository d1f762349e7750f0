#include "create.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common.hpp"
#include "protocol/assets_client.hpp"
#include "protocol/limits.hpp"
#include "protocol/names.hpp"
#include "protocol/text.hpp"
#include "scenario/bots_override.hpp"
#include "scenario/presets.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::cli {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(kExitRefused, "cannot read " + net::quoted(path));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// nlohmann's dump() recurses once per level: a 10^5-deep document would
// overflow the stack here before the server could refuse it.
int nestingDepth(const std::string& text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '{' || c == '[') deepest = std::max(deepest, ++depth);
    else if (c == '}' || c == ']') --depth;
  }
  return deepest;
}
constexpr int kMaxLocalDepth = 256;

std::string presetList() {
  std::string out;
  for (const auto& n : scenario::presetNames()) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

void addCreateOptions(CLI::App* cmd, CreateOptions& o, bool positional) {
  if (positional) cmd->add_option("SCENARIO", o.file, "scenario JSON file (validated by the server)")->required();
  else cmd->add_option("--create", o.file, "create the session from this scenario file first, then log it from seq 0");
  cmd->add_option("--mode", o.mode, "realtime | fast | lockstep")->capture_default_str()
      ->check(CLI::IsMember({"realtime", "fast", "lockstep"}));
  cmd->add_option("--rate", o.rate, "real-time factor")->capture_default_str()->check(positive());
  cmd->add_option("--publish-rate", o.publish_rate,
                  "state messages per simulated second (default: the scenario's output_rate)");
  // `log` has a --duration of its own (wall seconds to record)
  cmd->add_option(positional ? "--duration" : "--session-duration", o.duration,
                  "s of simulation; 0: the scenario's; < 0: until stopped")
      ->capture_default_str();
  cmd->add_option("--preset", o.preset, "speed/accuracy preset (" + presetList() + "), as `groundsim run --preset`")
      ->check(CLI::IsMember(scenario::presetNames()));
  cmd->add_option("--set", o.overrides, "override a scenario value, e.g. --set vehicle.placement.speed=2");
  cmd->add_option("--bots", o.bots, "a race: this many computer drivers, in cars of their own after the players'")
      ->check(CLI::Range(0, 64));
  cmd->add_option("--bot-skill", o.bot_skill, "a race: the bots' skill in [0.2, 1] (their throttle's cap)")
      ->check(CLI::Range(0.2, 1.0));
  cmd->add_option("--bot-policy", o.bot_policy,
                  "a race: the bots drive this trained policy file (examples/export_policy.py) instead of the "
                  "classical driver; sent with the scenario");
}

CreateRequest createRequest(const CreateOptions& o) {
  std::string text = readFile(o.file);
  if (!o.overrides.empty() || !o.preset.empty() || o.changesBots()) {
    // local changes need a parseable document; the server reports anything else
    if (nestingDepth(text) > kMaxLocalDepth)
      fail(kExitRefused, net::quoted(o.file) + ": nested deeper than " + std::to_string(kMaxLocalDepth) +
                             " levels, cannot apply --preset or --set");
    auto doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object())
      fail(kExitRefused, net::quoted(o.file) + ": not a JSON object, cannot apply --preset or --set");
    try {
      // precedence as in `groundsim run`: file < --preset < --set
      if (!o.preset.empty()) {
        doc["preset"] = o.preset;
        scenario::applyPreset(doc, /*force=*/true);
      }
      for (const auto& a : o.overrides) scenario::applyOverride(doc, a);
      if (o.changesBots()) {
        scenario::BotsChoice bots;
        bots.count = o.bots;  // -1: the race's own
        if (o.bot_skill > 0.0) bots.skill = o.bot_skill;
        // named as its path from here: the scenario's files are found next to it, this one where it is
        if (!o.bot_policy.empty()) bots.policy = std::filesystem::absolute(o.bot_policy).string();
        scenario::setBots(doc, bots);
      }
    } catch (const scenario::ScenarioError& e) {
      fail(kExitRefused, e.what());
    }
    text = doc.dump();
  }
  // the files it names travel with it, as hashes in its "assets" manifest
  net::ScenarioWithAssets sent;
  try {
    sent = net::withAssets(text, std::filesystem::path(o.file).parent_path().string());
  } catch (const scenario::ScenarioError& e) {
    fail(kExitRefused, net::quoted(o.file) + ": " + e.lines("; "));
  }
  text = std::move(sent.json);
  if (text.size() > net::kMaxScenarioBytes)
    fail(kExitRefused, net::quoted(o.file) + ": " + std::to_string(text.size()) +
                           " bytes, larger than the " + std::to_string(net::kMaxScenarioBytes) +
                           " bytes a create can carry (docs/protocol.md, Limits); not sent");
  groundsim::request_t req{};
  req.op = groundsim::request_t::OP_CREATE;
  req.scenario_json = std::move(text);
  req.mode = static_cast<int8_t>(net::modeFromName(o.mode));
  req.rate = o.rate;
  req.publish_rate = o.publish_rate;
  req.duration = o.duration;
  return {std::move(req), std::move(sent.assets)};
}

}  // namespace groundsim::cli
