// groundsim-server: hosts simulation sessions for LCM clients
// (docs/protocol.md). Stops cleanly on SIGINT or SIGTERM; in a fleet
// (--etcd, docs/fleet.md) it hands its sessions over first.
#include <chrono>
#include <thread>
#include <cctype>
#include <csignal>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "protocol/channels.hpp"
#include "protocol/limits.hpp"
#include "protocol/text.hpp"
#include "fleet_node.hpp"
#include "lcm_server.hpp"
#include "metrics.hpp"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

void onSignal(int) { g_stop.store(true); }

}  // namespace

namespace {

// Everything the command line sets.
struct ServerOptions {
  groundsim::session::ServiceConfig cfg;
  std::string url = groundsim::net::defaultUrl();
  double slice_ms = groundsim::session::ServiceConfig{}.slice * 1e3;
  bool quiet = false;
  groundsim::net::ResendLimits resend;
  int metrics_port = 0;
  double stop_linger = 1.0;
  std::string metrics_bind = "127.0.0.1";
  groundsim::net::FleetOptions fleet;
  std::string etcd;
  double snapshot_interval = 1.0;
  double heartbeat_period = 0;  // 0: 1 s alone, 0.25 s in a fleet
};

void addServiceOptions(CLI::App& app, ServerOptions& o) {
  app.add_option("--lcm-url", o.url, "LCM URL (recv_buf_size is added when missing)")->capture_default_str();
  app.add_option("--workers", o.cfg.workers, "stepping threads (0: one per core)")->capture_default_str()
      ->check(CLI::Range(0, 1024));
  app.add_option("--max-sessions", o.cfg.max_sessions, "concurrent sessions")->capture_default_str()->check(CLI::Range(1, 100000));
  app.add_option("--client-sessions", o.cfg.max_client_sessions,
                 "sessions one client (a create's client_id) may hold at once (0: no limit; docs/reliability.md)")
      ->capture_default_str()->check(CLI::Range(0, 100000));
  app.add_option("--client-creates", o.cfg.client_creates_per_minute,
                 "creates one client may make a minute, as a burst of that many then one every 60/n s (0: no limit)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--idle-timeout", o.cfg.idle_timeout, "s without owner activity before a session is reclaimed (0: never)")->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_option("--command-timeout", o.cfg.command_timeout, "s real time mode holds a car's drive command or pedals before zero torque (each car on its own)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-torque", o.cfg.max_torque, "N m, largest accepted drive or brake torque")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--slice-ms", o.slice_ms, "ms a session may step before yielding its worker")->capture_default_str()->check(CLI::Range(0.05, 1000.0));
  app.add_option("--publish-limit", o.cfg.publish_limit, "state messages per wall second per session (paced, not dropped)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-lag", o.cfg.max_lag, "s behind the wall clock before a real time session skips ahead")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-vehicles", o.cfg.max_vehicles, "vehicles per session")->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--max-envs", o.cfg.max_envs, "environments of one vectorised session (checked before building)")
      ->capture_default_str()->check(CLI::Range(1, 65536));
  app.add_flag("--quiet", o.quiet, "do not log events on stderr");
  app.add_option("--terrain-dir", o.cfg.terrain_dir,
                 "folder of server-side terrain files, for names a create does not send with its scenario (none: only sent files)")
      ->check(CLI::ExistingDirectory);
  // the files clients send with their scenarios (session/asset_store.hpp, docs/protocol.md Assets)
  app.add_option("--max-asset-bytes", o.cfg.assets.max_asset_bytes, "largest file a scenario may send with it")
      ->capture_default_str()->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 32));
  app.add_option("--max-session-asset-bytes", o.cfg.assets.max_session_bytes, "all files of one scenario")
      ->capture_default_str()->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 34));
  app.add_option("--asset-cache-bytes", o.cfg.assets.cache_bytes,
                 "files held in memory in all (sessions' files stay; others are evicted, least recently used first)")
      ->capture_default_str()->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 36));
  app.add_option("--max-scenario-bytes", o.cfg.max_scenario_bytes, "largest scenario a create may carry")
      ->capture_default_str()->check(CLI::Range(std::size_t{1}, groundsim::net::kMaxScenarioBytes));
  app.add_option("--max-build-jobs", o.cfg.max_build_jobs, "scene builds at once (0: workers - 1, at least 1)")
      ->capture_default_str()->check(CLI::Range(0, 1024));
}

// the model budget (scenario/budget.hpp, docs/reliability.md): every create is checked before building
void addBudgetOptions(CLI::App& app, ServerOptions& o) {
  auto& b = o.cfg.budget;
  app.add_option("--max-depth", b.max_depth, "nesting depth of a scenario document")->capture_default_str()
      ->check(CLI::Range(2, 10000));
  app.add_option("--max-json-values", b.max_json_values, "values in a scenario document")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-expression-length", b.max_expression_length, "characters of an expression ground")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-points", b.max_points, "mass and attachment points per session")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-springs", b.max_springs, "springs per session")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-particles", b.max_particles, "free point masses per session")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-state", b.max_state, "doubles in a session's state")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-implicit-state", b.max_implicit_state, "state size implicit_euler may factor densely")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--max-steps", b.max_steps, "integrator steps over a session's duration")->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-work", b.max_work, "estimated work over a session's duration")->capture_default_str()
      ->check(CLI::PositiveNumber);
}

// the recent frames kept for recorders' re-requests (docs/logging.md)
void addResendOptions(CLI::App& app, ServerOptions& o) {
  app.add_option("--resend-frames", o.resend.frames_per_session,
                 "recent frames per session kept for recorders' re-requests (docs/logging.md)")
      ->capture_default_str()->check(CLI::Range(1, 1 << 20));
  app.add_option("--resend-session-bytes", o.resend.bytes_per_session, "bytes of recent frames kept per session")
      ->capture_default_str()->check(CLI::Range(std::size_t{1024}, std::size_t{1} << 32));
  app.add_option("--resend-rate", o.resend.messages_per_s, "messages per second resent to one recorder")
      ->capture_default_str()->check(CLI::Range(1.0, 1e7));
}

void addMetricsOptions(CLI::App& app, ServerOptions& o) {
  // GET /metrics (Prometheus) and /health on a listener of their own (metrics.hpp, docs/metrics.md)
  app.add_option("--metrics-port", o.metrics_port, "TCP port of GET /metrics and /health (0: off)")
      ->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--metrics-bind", o.metrics_bind, "address the metrics port listens on (127.0.0.1: this machine only)")
      ->capture_default_str();
  app.add_option("--stop-linger", o.stop_linger,
                 "in a fleet with a metrics port: s that /health keeps answering 503 \"stopping\" after a drain "
                 "handed the sessions over, so that a balancer's health check sees the drain")
      ->capture_default_str()->check(CLI::Range(0.0, 60.0));
}

void addFleetOptions(CLI::App& app, ServerOptions& o) {
  app.add_option("--etcd", o.etcd, "join a fleet: etcd endpoints, comma separated (docs/fleet.md); without it a lone server");
  app.add_option("--server-id", o.fleet.server_id, "this server's id in the fleet (default: a random one)")
      ->check([](const std::string& s) {
        if (s.empty() || s.size() > 64) return std::string("1 to 64 characters");
        for (char c : s)
          if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-')
            return std::string("only letters, digits, '.', '_' and '-'");
        return std::string();
      });
  app.add_option("--address", o.fleet.address, "how the fleet reaches this server (informational, in its registration)");
  app.add_option("--placement", o.fleet.placement, "where a fleet places new sessions: spread (balance) or packed (fill one first)")
      ->capture_default_str()->check(CLI::IsMember({"spread", "packed"}));
  app.add_option("--snapshot-interval", o.snapshot_interval, "s of simulated time between a session's snapshots for its standbys (fleet)")
      ->capture_default_str()->check(CLI::Range(0.01, 3600.0));
  app.add_option("--heartbeat-period", o.heartbeat_period,
                 "s between heartbeats (0: 1 s alone, 0.25 s in a fleet, where clients take a server silent for "
                 "3.5 periods for dead: docs/fleet.md)")
      ->capture_default_str()->check(CLI::Range(0.0, 10.0));
  app.add_option("--lease-ttl", o.fleet.ttl_s, "s, the fleet membership's lease (etcd's minimum is 2)")
      ->capture_default_str()->check(CLI::Range(2, 60));
}

// the values the options imply
void settle(ServerOptions& o) {
  o.cfg.slice = o.slice_ms * 1e-3;
  if (o.heartbeat_period <= 0) o.heartbeat_period = o.etcd.empty() ? 1.0 : 0.25;
  if (o.heartbeat_period < 0.05) o.heartbeat_period = 0.05;  // a flood of heartbeats helps nobody
  o.fleet.heartbeat_period = std::chrono::milliseconds(static_cast<int>(o.heartbeat_period * 1000));
  if (!o.etcd.empty()) o.cfg.replica_interval = o.snapshot_interval;
}

void installSignals() {
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);
}

// --etcd: this server joins the fleet (its sessions' ownership through etcd)
std::unique_ptr<groundsim::net::FleetNode> joinFleet(groundsim::net::LcmServer& server, ServerOptions& o) {
  if (o.etcd.empty()) return nullptr;
  if (!o.fleet.server_id.empty()) server.setServerId(o.fleet.server_id);
  o.fleet.server_id = server.serverId();
  o.fleet.endpoints = groundsim::fleet::EtcdClient::parseEndpoints(o.etcd);
  o.fleet.build = "groundsim-server";
  auto node = std::make_unique<groundsim::net::FleetNode>(o.fleet, server.service(), server);
  server.service().setOwnership(node.get());
  server.setFleet(node.get());
  std::printf("fleet: server %s joined through %s (placement %s, lease %lld s, snapshots every %g s)\n",
              o.fleet.server_id.c_str(), o.etcd.c_str(), o.fleet.placement.c_str(),
              static_cast<long long>(node->membership().ttl()), o.snapshot_interval);
  return node;
}

void printReady(const groundsim::net::LcmServer& server, const ServerOptions& o,
                const groundsim::net::MetricsListener* metrics) {
  const auto& cfg = o.cfg;
  std::printf("groundsim-server ready on %s with %d workers, up to %d sessions\n", server.url().c_str(),
              server.workers(), cfg.max_sessions);
  const auto& lim = server.config().budget;
  std::printf("limits: scenario %zu bytes, depth %d, %d vehicles, %lld points, %lld springs, %lld particles, "
              "state %lld, implicit state %lld, %g steps, %g work; rate [%g, %g], publish rate [%g, %g] Hz; %d envs per vectorised session; "
              "assets %llu bytes per file, %llu per scenario, %llu held\n",
              lim.max_document_bytes, lim.max_depth, lim.max_vehicles, lim.max_points, lim.max_springs,
              lim.max_particles, lim.max_state, lim.max_implicit_state, lim.max_steps, lim.max_work, cfg.min_rate,
              cfg.max_rate, cfg.min_publish_rate, cfg.max_publish_rate, cfg.max_envs,
              static_cast<unsigned long long>(cfg.assets.max_asset_bytes),
              static_cast<unsigned long long>(cfg.assets.max_session_bytes),
              static_cast<unsigned long long>(cfg.assets.cache_bytes));
  if (metrics) std::printf("metrics on http://%s:%u/metrics and /health\n", o.metrics_bind.c_str(), metrics->port());
  std::fflush(stdout);
}

// Serves until SIGINT or SIGTERM: the fleet joined, the metrics listener up
// before the ready line (whoever waits for it can scrape) and stopped after
// the sessions (/health answers 503 while they stop), then the fleet left.
int serve(ServerOptions& o) {
  groundsim::net::LcmServer server(o.url, o.cfg, !o.quiet);
  server.setResendLimits(o.resend);
  server.setHeartbeatPeriod(o.heartbeat_period);
  std::unique_ptr<groundsim::net::FleetNode> node = joinFleet(server, o);
  std::unique_ptr<groundsim::net::MetricsListener> metrics;
  if (o.metrics_port > 0)
    metrics = std::make_unique<groundsim::net::MetricsListener>(
        o.metrics_bind, static_cast<unsigned short>(o.metrics_port), groundsim::net::serverMetricsHandler(server, g_stop));
  printReady(server, o, metrics.get());
  server.run(g_stop);
  // a balancer polls /health every second or so: a drain that handed its
  // sessions over in milliseconds would otherwise show it a refused
  // connection, not "stopping" (docs/metrics.md)
  if (metrics && node && o.stop_linger > 0) std::this_thread::sleep_for(std::chrono::duration<double>(o.stop_linger));
  metrics.reset();
  server.service().setOwnership(nullptr);
  node.reset();  // leaves the fleet
  std::printf("groundsim-server stopped\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ServerOptions o;
  CLI::App app{"groundsim-server: simulation sessions over LCM"};
  addServiceOptions(app, o);
  addBudgetOptions(app, o);
  addResendOptions(app, o);
  addMetricsOptions(app, o);
  addFleetOptions(app, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // exit 2 for every usage error (CLI11's own codes are 105, 106, ...); values escaped and cut
    std::fprintf(stderr, "groundsim-server: %s (see --help)\n", groundsim::net::printable(e.what(), 300).c_str());
    return 2;
  }
  settle(o);
  installSignals();
  try {
    return serve(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundsim-server: %s\n", e.what());
    return 2;
  }
}
