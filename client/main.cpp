// groundsim: the embedded runner and the clients of groundsim-server.
//
// Exit codes (README, docs/protocol.md): 0 done; 2 a usage error (unknown
// subcommand or option, bad or missing value; the message names it, with
// user text quoted, escaped and cut); other codes are the subcommand's own
// (run: 1 output, 2 invalid scenario, 3 diverged, 4 out of memory; network
// commands: 1 refused, 3 log loss, 4 no server; replay --resimulate: 1 not
// re-simulable, 5 a state differs, docs/logging.md).
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "protocol/text.hpp"

namespace {

constexpr int kExitUsage = 2;

// The first word that is not an option, when it names no subcommand.
std::string unknownSubcommand(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->check_name(argv[1])) return "";
  return argv[1];
}

std::string subcommandNames(const CLI::App& app) {
  std::string out;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    out += (out.empty() ? "" : ", ") + sub->get_name();
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"groundsim: four-wheel vehicles on arbitrary grounds"};
  app.require_subcommand(1);
  groundsim::cli::registerRunCommand(app);
  groundsim::cli::registerNetworkCommands(app);
  const std::string unknown = unknownSubcommand(app, argc, argv);
  if (!unknown.empty()) {
    std::fprintf(stderr, "groundsim: unknown subcommand %s (one of: %s; see groundsim --help)\n",
                 groundsim::net::quoted(unknown).c_str(), subcommandNames(app).c_str());
    return kExitUsage;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a subcommand's own result, already reported
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // CLI11's messages repeat the offending value: escape and cut it
    std::fprintf(stderr, "groundsim: %s (see groundsim %s--help)\n", groundsim::net::printable(e.what(), 300).c_str(),
                 argc > 1 && argv[1][0] != '-' ? (groundsim::net::printable(argv[1], 20) + " ").c_str() : "");
    return kExitUsage;
  }
  return 0;
}
