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

int main(int argc, char** argv) {
  using namespace groundsim::web;
  CLI::App app{"groundsim-web: drive and watch groundsim sessions in a browser"};
  std::string bind = "127.0.0.1";
  int port = 8080;
  std::string recordings_dir;
  std::string lcm_url = groundsim::net::defaultUrl();
  std::string static_dir = GROUNDSIM_WEB_DIST;
  HubConfig cfg;
  cfg.configs_dir = GROUNDSIM_CONFIG_DIR;
  bool quiet = false;
  app.add_option("--bind", bind, "address to listen on (127.0.0.1: this machine only)")->capture_default_str();
  app.add_option("--port", port, "TCP port of the page, the WebSocket, GET /metrics and /health (0: any free one, printed)")->capture_default_str()->check(CLI::Range(0, 65535));
  app.add_option("--lcm-url", lcm_url, "LCM URL of the server's bus")->capture_default_str();
  app.add_option("--recordings", recordings_dir,
                 "folder of MCAP recordings served at /recordings, with seeking (docs/logging.md); none by default");
  app.add_option("--static", static_dir, "folder of the bundled page (index.html, bundle.js)")->capture_default_str();
  app.add_option("--configs", cfg.configs_dir, "scenarios a browser may create sessions from (*.json, subfolders too)")
      ->capture_default_str();
  app.add_option("--max-vehicles", cfg.max_vehicles,
                 "the server's --max-vehicles: the lobby offers at most this many cars (and at most " +
                     std::to_string(kMaxCreateVehicles) + ")")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  app.add_option("--drive-torque", cfg.scale.drive_torque, "N m per wheel at full throttle")->capture_default_str();
  app.add_option("--brake-torque", cfg.scale.brake_torque, "N m per wheel at full brake")->capture_default_str();
  app.add_option("--steer", cfg.scale.steer, "rad of front-wheel steering at full lock")->capture_default_str();
  int foxglove_port = -1;
  foxglove::Options fox;
  app.add_option("--foxglove-port", foxglove_port,
                 "TCP port of a Foxglove WebSocket endpoint on --bind (Foxglove/Lichtblick: Open connection, Foxglove "
                 "WebSocket, ws://127.0.0.1:N; 0: any free one, printed; docs/logging.md); none by default")
      ->check(CLI::Range(0, 65535));
  app.add_option("--foxglove-outbox", fox.outbox,
                 "data messages a Foxglove client may fall behind by; the oldest are dropped beyond (counted)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  // what one browser may do (docs/front-end.md, Fairness): defaults for anonymous players on a public page
  BrowserLimits& lim = cfg.limits;
  app.add_option("--browser-sessions", lim.sessions,
                 "sessions one browser may own at once (those it created and that have not ended; 0: no limit)")
      ->capture_default_str()->check(CLI::Range(0, 1000));
  app.add_option("--browser-cars", lim.cars, "cars in a session a browser creates")
      ->capture_default_str()->check(CLI::Range(1, 64));
  std::string modes = joinModes(lim.modes);
  app.add_option("--browser-modes", modes, "modes a browser may create in (comma-separated: realtime,fast,lockstep)")
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
  app.add_option("--orphan-stop", cfg.orphan_stop_s,
                 "s after which a session a browser created and that nobody watches or drives is stopped")
      ->capture_default_str()->check(CLI::Range(1.0, 86400.0));
  app.add_flag("--quiet", quiet, "no connection and refusal log on stderr");
  CLI11_PARSE(app, argc, argv);
  cfg.log = !quiet;

  auto files = loadStaticFiles(static_dir);
  if (!files.count("/")) {
    std::fprintf(stderr, "groundsim-web: no index.html in %s (build the page: ninja groundsim_web_page)\n",
                 static_dir.c_str());
    return 1;
  }

  boost::asio::io_context io;
  Bus bus;
  LcmLink* link_ptr = nullptr;
  bus.request = [&](const groundsim::request_t& r) { link_ptr->publish(r); };
  bus.drive = [&](const groundsim::drive_t& d) { link_ptr->publish(d); };
  bus.controls = [&](const groundsim::controls_t& c) { link_ptr->publish(c); };
  bus.assets = [&](const std::vector<groundsim::scenario::Asset>& assets, const std::vector<groundsim::asset_want_t>& wants) {
    link_ptr->publishAssets(assets, wants);
  };
  // the hub needs the client id before the link exists: the link picks it
  std::unique_ptr<Hub> hub;
  LcmHandlers forward;
  LcmLink link(lcm_url, LcmHandlers{
                            [&](const auto& m) { if (forward.status) forward.status(m); },
                            [&](const auto& m) { if (forward.state) forward.state(m); },
                            [&](const auto& m) { if (forward.event) forward.event(m); },
                            [&](const auto& m) { if (forward.reply) forward.reply(m); },
                            [&](const auto& m) { if (forward.scenario) forward.scenario(m); },
                            [&](const auto& c, const auto& r) { if (forward.bad) forward.bad(c, r); },
                            [&](const auto& m) { if (forward.car_state) forward.car_state(m); }});
  if (!link.good()) {
    std::fprintf(stderr, "groundsim-web: cannot open LCM %s (no multicast route? ip route add 224.0.0.0/4 dev lo)\n",
                 lcm_url.c_str());
    return 1;
  }
  link_ptr = &link;
  bus.client_id = link.clientId();
  hub = std::make_unique<Hub>(io, cfg, bus);
  forward = hub->lcmHandlers();

  // objects and hits of scenes with contact between bodies, beside the states
  ContactFeed contacts(&link.bus(), ContactFeed::Hooks{
                                        [&](const std::string& id) { return hub->watched(id); },
                                        [&](const std::string& id, std::shared_ptr<const std::string> json) {
                                          hub->postToWatchers(id, Slot::Contact, std::move(json));
                                        },
                                        [&](const std::string& c, const std::string& r) {
                                          if (forward.bad) forward.bad(c, r);
                                        }});

  WebServer server(io, *hub, std::move(files), recordings_dir, cfg.configs_dir);
  try {
    server.listen(bind, static_cast<unsigned short>(port));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundsim-web: cannot listen on %s:%d: %s\n", bind.c_str(), port, e.what());
    return 1;
  }
  // live sessions for Foxglove and Lichtblick, on a port of their own (foxglove_server.hpp)
  std::unique_ptr<foxglove::Server> foxglove_server;
  if (foxglove_port >= 0) {
    fox.log = !quiet;
    foxglove_server = std::make_unique<foxglove::Server>(io, &link.bus(), fox,
                                                         [&](const std::string& c, const std::string& r) {
                                                           if (forward.bad) forward.bad(c, r);
                                                         });
    try {
      foxglove_server->listen(bind, static_cast<unsigned short>(foxglove_port));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "groundsim-web: cannot listen on %s:%d: %s\n", bind.c_str(), foxglove_port, e.what());
      return 1;
    }
    server.addMetrics([&] { return foxglove_server->metrics(); });
  }
  link.start();

  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code&, int) {
    hub->stopOwnedSessions();
    io.stop();
  });
  std::printf("groundsim-web: open http://%s:%u/ (LCM %s)\n", bind == "0.0.0.0" ? "127.0.0.1" : bind.c_str(),
              server.port(), lcm_url.c_str());
  if (foxglove_server)
    std::printf("groundsim-web: foxglove ws://%s:%u/\n", bind == "0.0.0.0" ? "127.0.0.1" : bind.c_str(),
                foxglove_server->port());
  std::fflush(stdout);
  io.run();
  link.stop();
  return 0;
}
