// What `groundsim create` and `groundsim log --create` share: the scenario
// options and the request they make. The scenario is read and prepared here
// (--preset, --set) exactly as `groundsim run` does, and refused before
// sending when it is larger than a create can carry.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <groundsim/request_t.hpp>

#include "scenario/assets.hpp"

namespace groundsim::cli {

struct CreateOptions {
  std::string file, mode = "realtime", preset;
  double rate = 1.0, publish_rate = 0.0, duration = 0.0;
  std::vector<std::string> overrides;
  // a race's computer drivers (docs/drivers.md): -1 keeps the scenario's
  int bots = -1;
  double bot_skill = 0.0;          // 0: the scenario's
  std::string bot_policy;          // a trained driver's policy file ("": the scenario's)
  bool changesBots() const { return bots >= 0 || bot_skill > 0.0 || !bot_policy.empty(); }
};

// SCENARIO is positional when `positional`, else the option --create (and
// the simulated duration is --session-duration).
void addCreateOptions(CLI::App* cmd, CreateOptions& o, bool positional);
// The OP_CREATE request and the files the scenario names (read next to it,
// as `groundsim run` reads them; sent when the server asks: NetClient::create).
struct CreateRequest {
  groundsim::request_t req;
  std::vector<scenario::Asset> assets;
};
// Ends the command (kExitRefused) when the file or a file it names cannot
// be read or prepared, or the scenario is too large for the transport.
CreateRequest createRequest(const CreateOptions& o);

}  // namespace groundsim::cli
