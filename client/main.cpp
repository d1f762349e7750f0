// groundsim: the embedded runner and the clients of groundsim-server.
#include <CLI/CLI.hpp>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"groundsim: four-wheel vehicles on arbitrary grounds"};
  app.require_subcommand(1);
  groundsim::cli::registerRunCommand(app);
  groundsim::cli::registerNetworkCommands(app);
  CLI11_PARSE(app, argc, argv);
  return 0;
}
