// Shared parts of the `groundsim` network subcommands (client/net/).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include <groundsim/reply_t.hpp>
#include <groundsim/state_t.hpp>

#include "client.hpp"

namespace groundsim::cli {

// Exit codes of the network commands (docs/protocol.md, Clients). 2 is
// every command's usage error (client/main.cpp).
inline constexpr int kExitRefused = 1;   // the server refused, or a local input problem (the reason on stderr)
inline constexpr int kExitUsage = 2;     // bad command line
inline constexpr int kExitLoss = 3;      // `log`: state messages were lost
inline constexpr int kExitNoServer = 4;  // no reply, no heartbeat, or LCM could not be opened

struct NetOptions {
  std::string url;
  double timeout = 2.0;      // s to wait for a reply
  std::string token_file;    // "" : defaultTokenFile()
  std::string token;         // explicit token, overrides the file
};

// CLI11's PositiveNumber says "not in range 0.000000 to 1797...(309 digits)":
// this says "must be a number > 0" and names the value, quoted and cut.
CLI::Validator positive();

// --lcm-url and --timeout on every command; --token-file / --token on those
// that need ownership (with_token).
void addNetOptions(CLI::App* cmd, NetOptions& o, bool with_token);
// The explicit --token, else the token file's entry, else "" (the server
// then refuses, naming the reason).
std::string tokenFor(const NetOptions& o, const std::string& session_id);

// Prints "groundsim: message" on stderr and ends the command with `code`.
[[noreturn]] void fail(int code, const std::string& message);
// Runs a command body, turning NetError into kExitNoServer.
void guarded(const std::function<void()>& body);

// SIGINT/SIGTERM end the long-running commands (watch, log, drive) cleanly.
void installStopSignals();
bool stopRequested();

// One line: "t=1.2 tick=24000 running car: x=.. speed=.. m/s" (names escaped and cut).
std::string stateLine(const groundsim::state_t& s);

void registerSessionCommands(CLI::App& app);  // create list stop reset pause resume mode step
void registerWatchCommand(CLI::App& app);
void registerLogCommand(CLI::App& app);
void registerRecordCommand(CLI::App& app);
void registerRecordingFileCommands(CLI::App& app);  // inspect, convert (client/record/file_commands.cpp)
void registerReplayCommand(CLI::App& app);  // replay --resimulate (client/record/replay.cpp)
void registerDriveCommand(CLI::App& app);

}  // namespace groundsim::cli
