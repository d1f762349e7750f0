// Options, token lookup and formatting shared by the network subcommands.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <sstream>

#include "channels.hpp"
#include "commands.hpp"
#include "net_commands.hpp"
#include "net_tokens.hpp"

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
  registerDriveCommand(app);
}

void addNetOptions(CLI::App* cmd, NetOptions& o, bool with_token) {
  o.url = net::defaultUrl();
  cmd->add_option("--lcm-url", o.url, "LCM URL of the server")->capture_default_str();
  cmd->add_option("--timeout", o.timeout, "s to wait for the server's reply")->capture_default_str()
      ->check(CLI::PositiveNumber);
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
  std::fprintf(stderr, "groundsim: %s\n", message.c_str());
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

const char* modeName(int mode) {
  switch (mode) {
    case groundsim::request_t::MODE_REALTIME: return "realtime";
    case groundsim::request_t::MODE_FAST: return "fast";
    case groundsim::request_t::MODE_LOCKSTEP: return "lockstep";
  }
  return "?";
}

int modeFromName(const std::string& name) {
  if (name == "realtime") return groundsim::request_t::MODE_REALTIME;
  if (name == "fast") return groundsim::request_t::MODE_FAST;
  if (name == "lockstep") return groundsim::request_t::MODE_LOCKSTEP;
  return 0;
}

const char* statusName(int status) {
  switch (status) {
    case groundsim::state_t::STATUS_RUNNING: return "running";
    case groundsim::state_t::STATUS_PAUSED: return "paused";
    case groundsim::state_t::STATUS_FINISHED: return "finished";
    case groundsim::state_t::STATUS_DIVERGED: return "diverged";
    case groundsim::state_t::STATUS_STOPPED: return "stopped";
  }
  return "?";
}

bool isFinal(int status) {
  return status == groundsim::state_t::STATUS_FINISHED || status == groundsim::state_t::STATUS_DIVERGED ||
         status == groundsim::state_t::STATUS_STOPPED;
}

std::string stateLine(const groundsim::state_t& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "t=%.3f tick=%lld seq=%lld %s", s.t, static_cast<long long>(s.tick),
                static_cast<long long>(s.seq), statusName(s.status));
  std::string out = buf;
  for (const auto& v : s.vehicles) {
    std::snprintf(buf, sizeof buf, "  %s: x=%.3f y=%.3f z=%.3f speed=%.3f m/s", v.name.c_str(), v.position[0],
                  v.position[1], v.position[2], v.speed);
    out += buf;
  }
  if (!s.status_reason.empty()) out += "  (" + s.status_reason + ")";
  return out;
}

}  // namespace groundsim::cli
