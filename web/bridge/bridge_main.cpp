// groundsim-web: the browser front end's bridge. One more LCM client of
// groundsim-server: it serves the page over HTTP, talks to browsers over
// WebSocket (JSON), subscribes to the sessions they watch and publishes the
// controls of the players it serves (docs/front-end.md).
#include <csignal>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>

#include "bridge/contact_feed.hpp"
#include "bridge/foxglove_server.hpp"
#include "bridge/hub.hpp"
#include "bridge/lcm_link.hpp"
#include "bridge/web_server.hpp"
#include "protocol/channels.hpp"

namespace {

using namespace groundsim::web;

// Everything the command line sets.
struct BridgeOptions {
  std::string bind = "127.0.0.1";
  int port = 8080;
  std::string recordings_dir;
  std::string lcm_url = groundsim::net::defaultUrl();
  std::string static_dir = GROUNDSIM_WEB_DIST;
  HubConfig cfg;
  bool quiet = false;
  int foxglove_port = -1;
  foxglove::Options fox;
  std::string modes;
  BridgeOptions() {
    cfg.configs_dir = GROUNDSIM_CONFIG_DIR;
    modes = joinModes(cfg.limits.modes);
  }
};

void addPageOptions(CLI::App& app, BridgeOptions& o) {
  app.add_option("--bind", o.bind, "address to listen on (127.0.0.1: this machine only)")->capture_default_str();
  app.add_option("--port", o.port, "TCP port of the page, the WebSocket, GET /metrics and /health (0: any free one, printed)")->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--lcm-url", o.lcm_url, "LCM URL of the server's bus")->capture_default_str();
  app.add_option("--recordings", o.recordings_dir,
                 "folder of MCAP recordings served at /recordings, with seeking (docs/logging.md); none by default");
  app.add_option("--static", o.static_dir, "folder of the bundled page (index.html, bundle.js)")->capture_default_str();
  app.add_option("--configs", o.cfg.configs_dir, "scenarios a browser may create sessions from (*.json, subfolders too)")
      ->capture_default_str();
  app.add_option("--max-vehicles", o.cfg.max_vehicles,
                 "the server's --max-vehicles: the lobby offers at most this many cars (and at most " +
                     std::to_string(kMaxCreateVehicles) + ")")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--drive-torque", o.cfg.scale.drive_torque, "N m per wheel at full throttle")->capture_default_str();
  app.add_option("--brake-torque", o.cfg.scale.brake_torque, "N m per wheel at full brake")->capture_default_str();
  app.add_option("--steer", o.cfg.scale.steer, "rad of front-wheel steering at full lock")->capture_default_str();
}

void addFoxgloveOptions(CLI::App& app, BridgeOptions& o) {
  app.add_option("--foxglove-port", o.foxglove_port,
                 "TCP port of a Foxglove WebSocket endpoint on --bind (Foxglove/Lichtblick: Open connection, Foxglove "
                 "WebSocket, ws://127.0.0.1:N; 0: any free one, printed; docs/logging.md); none by default")
      ->check(CLI::Range(0, 65535));
  app.add_option("--foxglove-outbox", o.fox.outbox,
                 "data messages a Foxglove client may fall behind by; the oldest are dropped beyond (counted)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
}

// what one browser may do (docs/front-end.md, Fairness): defaults for anonymous players on a public page
void addBrowserOptions(CLI::App& app, BridgeOptions& o) {
  BrowserLimits& lim = o.cfg.limits;
  app.add_option("--browser-sessions", lim.sessions,
                 "sessions one browser may own at once (those it created and that have not ended; 0: no limit)")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--browser-cars", lim.cars, "cars in a session a browser creates")
      ->capture_default_str()->check(CLI::Range(1, 64));
  app.add_option("--browser-modes", o.modes, "modes a browser may create in (comma-separated: realtime,fast,lockstep)")
      ->capture_default_str()
      ->check([&lim](const std::string& v) { return parseModes(v, lim.modes).value_or(""); });
  app.add_option("--browser-publish-rate", lim.publish_rate,
                 "Hz of states at most in a session a browser creates (0: no limit; the scenario's rate is held to it)")
      ->capture_default_str()->check(CLI::Range(0.0, 10000.0));
  app.add_option("--browser-creates", lim.creates_per_minute,
                 "creates a minute per browser: a burst of this many, then one every 60/n s (0: no limit)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--browser-messages", lim.messages_per_second,
                 "WebSocket messages a browser may send a second; beyond, the bridge reads its next one later (0: no limit)")
      ->capture_default_str()->check(CLI::Range(0.0, 1e6));
  app.add_option("--orphan-stop", o.cfg.orphan_stop_s,
                 "s after which a session a browser created and that nobody watches or drives is stopped")
      ->capture_default_str()->check(CLI::Range(1.0, 86400.0));
  app.add_flag("--quiet", o.quiet, "no connection and refusal log on stderr");
}

// The bridge's parts, wired: the LCM link (its client id first: the hub
// needs it), the hub, the contact feed, the page's server and the
// Foxglove endpoint. Handlers hold `this`: made in place, never moved.
class Bridge {
 public:
  explicit Bridge(BridgeOptions& o) : o_(o) {}
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;

  // 0, or the exit code after saying why not
  int start() {
    auto files = loadStaticFiles(o_.static_dir);
    if (!files.count("/")) {
      std::fprintf(stderr, "groundsim-web: no index.html in %s (build the page: ninja groundsim_web_page)\n",
                   o_.static_dir.c_str());
      return 1;
    }
    if (!openLink()) return 1;
    makeHub();
    if (!listen(std::move(files))) return 1;
    if (!startFoxglove()) return 1;
    link_->start();
    return 0;
  }

  void run() {
    boost::asio::signal_set signals(io_, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code&, int) {
      hub_->stopOwnedSessions();
      io_.stop();
    });
    const char* host = o_.bind == "0.0.0.0" ? "127.0.0.1" : o_.bind.c_str();
    std::printf("groundsim-web: open http://%s:%u/ (LCM %s)\n", host, server_->port(), o_.lcm_url.c_str());
    if (foxglove_) std::printf("groundsim-web: foxglove ws://%s:%u/\n", host, foxglove_->port());
    std::fflush(stdout);
    io_.run();
    link_->stop();
  }

 private:
  void bad(const std::string& c, const std::string& r) {
    if (forward_.bad) forward_.bad(c, r);
  }

  // the link forwards to the hub's handlers, set once the hub exists
  bool openLink() {
    link_ = std::make_unique<LcmLink>(o_.lcm_url, LcmHandlers{
        [this](const auto& m) { if (forward_.status) forward_.status(m); },
        [this](const auto& m) { if (forward_.state) forward_.state(m); },
        [this](const auto& m) { if (forward_.event) forward_.event(m); },
        [this](const auto& m) { if (forward_.reply) forward_.reply(m); },
        [this](const auto& m) { if (forward_.scenario) forward_.scenario(m); },
        [this](const auto& c, const auto& r) { bad(c, r); },
        [this](const auto& m) { if (forward_.car_state) forward_.car_state(m); }});
    if (link_->good()) return true;
    std::fprintf(stderr, "groundsim-web: cannot open LCM %s (no multicast route? ip route add 224.0.0.0/4 dev lo)\n",
                 o_.lcm_url.c_str());
    return false;
  }

  void makeHub() {
    bus_.request = [this](const groundsim::request_t& r) { link_->publish(r); };
    bus_.drive = [this](const groundsim::drive_t& d) { link_->publish(d); };
    bus_.controls = [this](const groundsim::controls_t& c) { link_->publish(c); };
    bus_.assets = [this](const std::vector<groundsim::scenario::Asset>& assets,
                         const std::vector<groundsim::asset_want_t>& wants) { link_->publishAssets(assets, wants); };
    bus_.client_id = link_->clientId();
    hub_ = std::make_unique<Hub>(io_, o_.cfg, bus_);
    forward_ = hub_->lcmHandlers();
    // objects and hits of scenes with contact between bodies, beside the states
    contacts_ = std::make_unique<ContactFeed>(
        &link_->bus(), ContactFeed::Hooks{[this](const std::string& id) { return hub_->watched(id); },
                                          [this](const std::string& id, std::shared_ptr<const std::string> json) {
                                            hub_->postToWatchers(id, Slot::Contact, std::move(json));
                                          },
                                          [this](const std::string& c, const std::string& r) { bad(c, r); }});
  }

  bool listen(std::map<std::string, StaticFile> files) {
    server_ = std::make_unique<WebServer>(io_, *hub_, std::move(files), o_.recordings_dir, o_.cfg.configs_dir);
    try {
      server_->listen(o_.bind, static_cast<unsigned short>(o_.port));
      return true;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "groundsim-web: cannot listen on %s:%d: %s\n", o_.bind.c_str(), o_.port, e.what());
      return false;
    }
  }

  // live sessions for Foxglove and Lichtblick, on a port of their own (foxglove_server.hpp)
  bool startFoxglove() {
    if (o_.foxglove_port < 0) return true;
    o_.fox.log = !o_.quiet;
    foxglove_ = std::make_unique<foxglove::Server>(io_, &link_->bus(), o_.fox,
                                                   [this](const std::string& c, const std::string& r) { bad(c, r); });
    try {
      foxglove_->listen(o_.bind, static_cast<unsigned short>(o_.foxglove_port));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "groundsim-web: cannot listen on %s:%d: %s\n", o_.bind.c_str(), o_.foxglove_port, e.what());
      return false;
    }
    server_->addMetrics([this] { return foxglove_->metrics(); });
    return true;
  }

  BridgeOptions& o_;
  boost::asio::io_context io_;
  Bus bus_;
  std::unique_ptr<Hub> hub_;  // destroyed after the link, as its handlers call it
  LcmHandlers forward_;
  std::unique_ptr<LcmLink> link_;
  std::unique_ptr<ContactFeed> contacts_;
  std::unique_ptr<WebServer> server_;
  std::unique_ptr<foxglove::Server> foxglove_;
};

}  // namespace

int main(int argc, char** argv) {
  BridgeOptions o;
  CLI::App app{"groundsim-web: drive and watch groundsim sessions in a browser"};
  addPageOptions(app, o);
  addFoxgloveOptions(app, o);
  addBrowserOptions(app, o);
  CLI11_PARSE(app, argc, argv);
  o.cfg.log = !o.quiet;
  Bridge bridge(o);
  if (const int code = bridge.start(); code != 0) return code;
  bridge.run();
  return 0;
}
