// `groundsim create|list|stop|reset|pause|resume|mode|step`: one request,
// one reply each.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common.hpp"
#include "create.hpp"
#include "protocol/names.hpp"
#include "protocol/text.hpp"
#include "tokens.hpp"

namespace groundsim::cli {
namespace {

using groundsim::request_t;

// Ends with kExitRefused (printing the server's reason) unless r.ok.
void expectOk(const groundsim::reply_t& r) {
  if (!r.ok) fail(kExitRefused, (r.session_id.empty() ? "" : "session " + r.session_id + ": ") + r.error);
  // (fail() escapes control characters; the server quotes and cuts user strings)
}

// Sends a session request carrying the owner's token and checks the reply.
groundsim::reply_t ownerCall(const NetOptions& o, const std::string& session, int8_t op,
                             const std::function<void(request_t&)>& fill = {}) {
  NetClient client(o.url);
  request_t req{};
  req.op = op;
  req.session_id = session;
  req.token = tokenFor(o, session);
  if (fill) fill(req);
  groundsim::reply_t r = client.call(req, o.timeout);
  if (!r.ok && req.token.empty())
    r.error += " (no token for it in " + TokenStore(o.token_file).path() + "; pass --token or --token-file)";
  expectOk(r);
  return r;
}

void printExact(const groundsim::state_t& s) {
  // %.17g: every double printed exactly, so two runs compare bit for bit
  for (const auto& v : s.vehicles) {
    std::printf("%" PRId64 " %.17g %s %s", s.tick, s.t, net::printable(v.name, 64).c_str(), net::statusName(s.status));
    for (double x : v.position) std::printf(" %.17g", x);
    for (double x : v.orientation) std::printf(" %.17g", x);
    for (double x : v.velocity) std::printf(" %.17g", x);
    for (double x : v.angular_velocity) std::printf(" %.17g", x);
    for (double x : v.wheel_spin) std::printf(" %.17g", x);
    std::printf(" %.17g\n", s.energy);
  }
}

void addCreate(CLI::App& app) {
  struct Opts {
    NetOptions net;
    CreateOptions create;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("create", "create a session on groundsim-server from a scenario file");
  addCreateOptions(cmd, o->create, /*positional=*/true);
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] {
    guarded([&] {
      const CreateRequest req = createRequest(o->create);
      NetClient client(o->net.url);
      // building may take a while
      const groundsim::reply_t r = client.create(req.req, req.assets, std::max(o->net.timeout, 10.0));
      expectOk(r);
      TokenStore store(o->net.token_file);
      store.put(r.session_id, r.token, client.url());
      if (!r.sessions.empty()) {
        const auto& s = r.sessions.front();
        std::printf("created session %s: scenario %s, %s x%g, %g Hz, %d vehicle(s); token in %s\n",
                    net::printable(r.session_id).c_str(), net::quoted(s.name).c_str(), net::modeName(s.mode), s.rate,
                    s.publish_rate, s.nvehicles, store.path().c_str());
      }
      std::printf("%s\n", net::printable(r.session_id).c_str());  // last line: the id, for scripts
    });
  });
}

void addList(CLI::App& app) {
  auto o = std::make_shared<NetOptions>();
  auto* cmd = app.add_subcommand("list", "list the sessions of groundsim-server");
  addNetOptions(cmd, *o, false);
  cmd->callback([o] {
    guarded([&] {
      NetClient client(o->url);
      request_t req{};
      req.op = request_t::OP_LIST;
      const groundsim::reply_t r = client.call(req, o->timeout);
      expectOk(r);
      // SERVER and EPOCH: the owner in a fleet (docs/fleet.md); epoch 0 on a lone server
      std::printf("%-8s  %-16s  %-10s  %-8s  %10s  %12s  %6s  %8s  %5s  %7s  %-16s  %5s  %s\n", "SESSION", "NAME",
                  "MODE", "STATUS", "T [s]", "TICK", "RATE", "DT [s]", "ENVS", "IDLE[s]", "SERVER", "EPOCH",
                  "VEHICLES [WHEELS]");
      for (const auto& s : r.sessions) {
        std::string vehicles;
        for (size_t v = 0; v < s.vehicle_names.size(); ++v)
          vehicles += (vehicles.empty() ? "" : ",") + s.vehicle_names[v] +
                      (v < s.wheel_counts.size() ? "[" + std::to_string(s.wheel_counts[v]) + "]" : "");
        std::printf("%-8s  %-16s  %-10s  %-8s  %10.3f  %12" PRId64 "  %6g  %8g  %5d  %7.1f  %-16s  %5" PRId64 "  %s\n",
                    net::printable(s.session_id, 16).c_str(), net::printable(s.name, 40).c_str(),
                    net::modeName(s.mode), net::statusName(s.status), s.utime * 1e-6, s.tick, s.rate, s.dt,
                    s.num_envs, s.idle_s, net::printable(s.server_id.empty() ? "-" : s.server_id, 64).c_str(),
                    s.epoch, net::printable(vehicles).c_str());
      }
    });
  });
}

// stop, reset, pause, resume: the session id and nothing else.
void addSimple(CLI::App& app, const char* name, const char* help, int8_t op) {
  struct Opts {
    NetOptions net;
    std::string session;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand(name, help);
  cmd->add_option("SESSION", o->session, "session id")->required();
  addNetOptions(cmd, o->net, true);
  cmd->callback([o, op, name] {
    guarded([&] {
      ownerCall(o->net, o->session, op);
      if (op == request_t::OP_STOP) TokenStore(o->net.token_file).erase(o->session);
      std::printf("%s %s: ok\n", name, net::printable(o->session).c_str());
    });
  });
}

void addMode(CLI::App& app) {
  struct Opts {
    NetOptions net;
    std::string session, mode;
    double rate = 0.0, publish_rate = 0.0;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("mode", "change a session's mode, real-time factor or publish rate");
  cmd->add_option("SESSION", o->session, "session id")->required();
  cmd->add_option("MODE", o->mode, "realtime | fast | lockstep (default: unchanged)")
      ->check(CLI::IsMember({"realtime", "fast", "lockstep"}));
  cmd->add_option("--rate", o->rate, "real-time factor")->check(positive());
  cmd->add_option("--publish-rate", o->publish_rate, "state messages per simulated second")->check(positive());
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] {
    guarded([&] {
      const auto r = ownerCall(o->net, o->session, request_t::OP_SET_MODE, [&](request_t& req) {
        req.mode = static_cast<int8_t>(o->mode.empty() ? 0 : net::modeFromName(o->mode));
        req.rate = o->rate;
        req.publish_rate = o->publish_rate;
      });
      if (!r.sessions.empty())
        std::printf("%s: %s x%g, %g Hz\n", net::printable(o->session).c_str(), net::modeName(r.sessions[0].mode), r.sessions[0].rate,
                    r.sessions[0].publish_rate);
    });
  });
}

void addStep(CLI::App& app) {
  struct Opts {
    NetOptions net;
    std::string session;
    std::int64_t steps = 1;
    int repeat = 1;
    bool exact = false;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("step", "advance a lockstep session by N steps and print its state");
  cmd->add_option("SESSION", o->session, "session id")->required();
  cmd->add_option("N", o->steps, "steps per request")->required()->check(positive());
  cmd->add_option("--repeat", o->repeat, "requests to send, one after the other")->capture_default_str()
      ->check(positive());
  cmd->add_flag("--exact", o->exact, "print every state number exactly (%.17g), one line per vehicle");
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] {
    guarded([&] {
      NetClient client(o->net.url);
      request_t req{};
      req.op = request_t::OP_STEP;
      req.session_id = o->session;
      req.token = tokenFor(o->net, o->session);
      req.steps = o->steps;
      // the reply comes after the steps: allow for their simulation time
      for (int i = 0; i < o->repeat; ++i) {
        const groundsim::reply_t r = client.call(req, o->net.timeout + 1e-4 * static_cast<double>(o->steps));
        expectOk(r);
        if (r.states.empty()) fail(kExitRefused, "step reply without a state");
        if (o->exact) printExact(r.states.front());
        else std::printf("%s\n", stateLine(r.states.front()).c_str());
      }
    });
  });
}

// A race's respawn: OP_RESET with steps = -1 - vehicle (docs/protocol.md).
void addRespawn(CLI::App& app) {
  struct Opts {
    NetOptions net;
    std::string session;
    int vehicle = 0;
  };
  auto o = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("respawn", "put a race's car back at its last gate, upright and at rest");
  cmd->add_option("SESSION", o->session, "session id")->required();
  cmd->add_option("--vehicle", o->vehicle, "vehicle index in the scenario")->capture_default_str()
      ->check(CLI::Range(0, 1 << 20));
  addNetOptions(cmd, o->net, true);
  cmd->callback([o] {
    guarded([&] {
      ownerCall(o->net, o->session, request_t::OP_RESET, [&](request_t& req) { req.steps = -1 - o->vehicle; });
      std::printf("respawn %s vehicle %d: ok\n", net::printable(o->session).c_str(), o->vehicle);
    });
  });
}

}  // namespace

void registerSessionCommands(CLI::App& app) {
  addCreate(app);
  addList(app);
  addSimple(app, "stop", "stop a session (it publishes a last state with status stopped)", request_t::OP_STOP);
  addSimple(app, "reset", "restart a session from its initial state", request_t::OP_RESET);
  addSimple(app, "pause", "pause a real time or fast session", request_t::OP_PAUSE);
  addSimple(app, "resume", "resume a paused session", request_t::OP_RESUME);
  addRespawn(app);
  addMode(app);
  addStep(app);
}

}  // namespace groundsim::cli
