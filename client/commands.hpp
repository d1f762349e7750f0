// Each group of `groundsim` subcommands registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace groundsim::cli {

// `groundsim run`: the embedded runner (no network).
void registerRunCommand(CLI::App& app);
// `groundsim create|list|watch|drive|step|log|stop`: LCM clients.
void registerNetworkCommands(CLI::App& app);

}  // namespace groundsim::cli
