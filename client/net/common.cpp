// Options, token lookup and formatting shared by the network subcommands.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "commands.hpp"
#include "common.hpp"
#include "protocol/channels.hpp"
#include "protocol/names.hpp"
#include "protocol/text.hpp"
#include "tokens.hpp"

namespace groundsim::cli {
namespace {
std::atomic<bool> g_stop{false};
void onStopSignal(int) { g_stop.store(true); }
}  // namespace

void installStopSignals() {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool stopRequested() { return g_stop.load(); }

void registerNetworkCommands(CLI::App& app) {
  registerSessionCommands(app);
  registerWatchCommand(app);
  registerLogCommand(app);
  registerRecordCommand(app);
  registerRecordingFileCommands(app);
  registerReplayCommand(app);
  registerDriveCommand(app);
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !(x > 0))
          return "must be a number > 0, got " + net::quoted(text, 40);
        return "";
      },
      "POSITIVE");
}

void addNetOptions(CLI::App* cmd, NetOptions& o, bool with_token) {
  o.url = net::defaultUrl();
  cmd->add_option("--lcm-url", o.url, "LCM URL of the server")->capture_default_str();
  cmd->add_option("--timeout", o.timeout, "s to wait for the server's reply")->capture_default_str()
      ->check(positive());
  if (with_token) {
    cmd->add_option("--token-file", o.token_file, "session tokens (default " + defaultTokenFile() + ")");
    cmd->add_option("--token", o.token, "the session's token (instead of the token file)");
  }
}

std::string tokenFor(const NetOptions& o, const std::string& session_id) {
  if (!o.token.empty()) return o.token;
  return TokenStore(o.token_file).get(session_id).value_or("");
}

void fail(int code, const std::string& message) {
  // messages quote what users and servers sent; escape what is left, cut nothing of ours
  std::fprintf(stderr, "groundsim: %s\n", net::printable(message, 4000).c_str());
  throw CLI::RuntimeError(code);
}

void guarded(const std::function<void()>& body) {
  try {
    body();
  } catch (const NetError& e) {
    fail(kExitNoServer, e.what());
  } catch (const CLI::Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(kExitRefused, e.what());
  }
}

std::string stateLine(const groundsim::state_t& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "t=%.3f tick=%lld seq=%lld %s", s.t, static_cast<long long>(s.tick),
                static_cast<long long>(s.seq), net::statusName(s.status));
  std::string out = buf;
  for (const auto& v : s.vehicles) {
    std::snprintf(buf, sizeof buf, "  %s: x=%.3f y=%.3f z=%.3f speed=%.3f m/s", net::printable(v.name, 40).c_str(), v.position[0],
                  v.position[1], v.position[2], v.speed);
    out += buf;
  }
  if (!s.status_reason.empty()) out += "  (" + net::printable(s.status_reason) + ")";
  return out;
}

}  // namespace groundsim::cli
