#include "bridge/hub.hpp"

#include <cstdio>

#include <boost/asio/post.hpp>

#include "bridge/state_json.hpp"
#include "lcm/latency_trace.hpp"

namespace groundsim::web {

namespace asio = boost::asio;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

std::shared_ptr<const std::string> shared(std::string s) { return std::make_shared<const std::string>(std::move(s)); }

}  // namespace

Hub::Hub(asio::io_context& io, HubConfig cfg, Bus bus)
    : io_(io),
      cfg_(std::move(cfg)),
      bus_(std::move(bus)),
      ticker_(io),
      browsers_(cfg_.limits, cfg_.log),
      requests_(io, bus_.request, bus_.client_id, cfg_.reply_timeout_s),
      lobby_(io, browsers_, sessions_),
      previews_(io, worker_, browsers_, cfg_.configs_dir),
      creates_(context(), scenarios_, [this](Peer* p, const JoinMsg& j) { seats_.join(p, j); }),
      seats_(context(), lobby_, creates_) {
  offerScenarios();
  tick();
}

HubContext Hub::context() { return HubContext{io_, worker_, cfg_, bus_, browsers_, sessions_, requests_}; }

Hub::~Hub() {
  worker_.stop();  // before the parts its jobs refer to
  ticker_.cancel();
}

// Every scenario under configs_dir, with its description and how many cars
// it hosts (shipped_scenarios.hpp), sent to each browser as it connects.
void Hub::offerScenarios() {
  const ShippedList list =
      listShippedScenarios(cfg_.configs_dir, cfg_.vehicle_margin,
                           std::min({kMaxCreateVehicles, cfg_.max_vehicles,
                                     cfg_.limits.cars > 0 ? cfg_.limits.cars : kMaxCreateVehicles}));
  json offered = json::array();
  for (const ShippedScenario& sc : list.scenarios) {
    configs_.push_back(sc.id);
    scenarios_[sc.id] = sc;
    offered.push_back({{"id", sc.id}, {"name", sc.name}, {"description", sc.description}, {"vehicles", sc.vehicles},
                       {"min_cars", sc.min_cars}, {"max_cars", sc.max_cars}, {"limit", sc.limit},
                       {"race", sc.race}, {"bots", sc.bots}, {"grid", sc.grid}});
  }
  if (cfg_.log) {
    std::fprintf(stderr, "groundsim-web: %zu scenarios from %s\n", configs_.size(), cfg_.configs_dir.c_str());
    for (const std::string& why : list.skipped) std::fprintf(stderr, "groundsim-web: not offered: %s\n", why.c_str());
  }
  welcome_ = shared(json{{"op", "welcome"}, {"configs", configs_}, {"scenarios", offered},
                         {"max_message_bytes", kMaxMessageBytes}}.dump());
}

// ---- LCM thread -------------------------------------------------------------

LcmHandlers Hub::lcmHandlers() {
  LcmHandlers h;
  h.status = [this](const groundsim::server_status_t& s) { asio::post(io_, [this, s] { lobby_.onStatus(s); }); };
  h.state = [this](const groundsim::state_t& s) { onState(s); };
  h.car_state = [this](const groundsim::car_state_t& s) {
    if (!sessions_.watched(s.session_id)) return;
    postToWatchers(s.session_id, Slot::Car, shared(carStateJson(s)));
  };
  h.event = [this](const groundsim::event_t& e) {
    auto json = shared(eventJson(e));
    asio::post(io_, [this, e, json] { onEvent(e, json); });
  };
  h.reply = [this](const groundsim::reply_t& r) {
    if (requests_.ours(r.client_id)) asio::post(io_, [this, r] { requests_.onReply(r); });
  };
  h.scenario = [this](const groundsim::scenario_t& s) { asio::post(io_, [this, s] { seats_.onScenario(s); }); };
  h.asset_want = [this](const groundsim::asset_want_t& w) {
    if (requests_.ours(w.client_id)) asio::post(io_, [this, w] { creates_.noteWant(w); });
  };
  h.bad = [this](const std::string& channel, const std::string& reason) {
    ++undecodable_;
    if (cfg_.log) std::fprintf(stderr, "groundsim-web: undecodable message on %s: %s\n", channel.c_str(), reason.c_str());
  };
  return h;
}

void Hub::onState(const groundsim::state_t& s) {
  const std::string& id = s.session_id;
  if (net::LatencyTrace::on())
    net::LatencyTrace::line("srx %s %lld %lld", id.c_str(), static_cast<long long>(s.seq),
                            static_cast<long long>(net::LatencyTrace::nowUs()));
  if (!sessions_.noteBusState(id, s.t, Clock::now())) return;
  // re-encoded once, shared by every browser watching
  const double wall = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
  postToWatchers(id, Slot::State, shared(stateJson(s, wall)));
}

// ---- browsers -----------------------------------------------------------------

void Hub::attach(Peer* p) {
  browsers_.attach(p);
  p->send(welcome_);
  lobby_.publish();
  if (cfg_.log) std::fprintf(stderr, "groundsim-web: browser %s connected\n", p->describe().c_str());
}

void Hub::detach(Peer* p) {
  if (!browsers_.attached(p)) return;
  seats_.leave(p);
  browsers_.detach(p);
  for (auto& [id, s] : sessions_) std::erase_if(s.pending, [p](const auto& j) { return j.first == p; });
  if (cfg_.log) std::fprintf(stderr, "groundsim-web: browser %s disconnected\n", p->describe().c_str());
}

void Hub::onBinary(Peer* p) { browsers_.refuse(p, "", "", "binary messages are not accepted: send JSON text"); }

void Hub::onText(Peer* p, const std::string& text) {
  PeerState* ps = browsers_.find(p);
  if (!ps) return;
  ParsedMessage m = parseBrowserMessage(text);
  if (!m.message) return browsers_.refuse(p, m.op, m.error.field, m.error.reason);
  try {
    handle(p, *ps, *m.message);
  } catch (const std::exception& e) {
    // nothing a browser sends may take the bridge down
    browsers_.refuse(p, m.op, "", std::string("internal error: ") + e.what());
  }
}

void Hub::handle(Peer* p, PeerState& ps, const BrowserMessage& m) {
  if (auto* c = std::get_if<ControlsMsg>(&m)) return controls(p, ps, *c);
  if (auto* g = std::get_if<GroundMsg>(&m)) return ground(p, ps, *g);
  if (auto* j = std::get_if<JoinMsg>(&m)) return seats_.join(p, *j);
  if (auto* v = std::get_if<PreviewMsg>(&m)) {
    if (!scenarios_.count(v->config))
      return browsers_.refuse(p, "preview", "/config", "no shipped scenario named \"" + v->config + "\"");
    return previews_.ask(p, v->config);
  }
  if (auto* c = std::get_if<CreateMsg>(&m)) return creates_.create(p, ps, *c);
  if (auto* o = std::get_if<SessionOpMsg>(&m)) return sessionOp(p, ps, *o);
  if (std::get_if<LeaveMsg>(&m)) {
    seats_.leave(p);
    return Browsers::send(p, R"({"op":"left"})");
  }
  if (auto* ping = std::get_if<PingMsg>(&m)) return pong(p, *ping);
}

void Hub::pong(Peer* p, const PingMsg& m) {
  const PeerStats st = p->stats();
  char b[256];
  std::snprintf(b, sizeof b,
                "{\"op\":\"pong\",\"t\":%.17g,\"states_sent\":%llu,\"states_skipped\":%llu,\"queued\":%zu,"
                "\"waiting_bytes\":%zu,\"send_buffer\":%d}",
                m.t, static_cast<unsigned long long>(st.states_sent),
                static_cast<unsigned long long>(st.states_skipped), st.queued, st.waiting_bytes, st.send_buffer);
  Browsers::send(p, b);
}

// A browser cannot flood the server: at most one command per period each
// (controls_throttle.hpp).
void Hub::controls(Peer* p, PeerState& ps, const ControlsMsg& m) {
  if (ps.role != Role::Drive || !ps.throttle)
    return browsers_.refuse(p, "controls", "", "not driving a vehicle (join with role drive first)");
  ps.throttle->submit(m);
}

void Hub::sessionOp(Peer* p, PeerState& ps, const SessionOpMsg& m) {
  if (ps.role != Role::Drive) return browsers_.refuse(p, m.op, "", "only a driver may " + m.op + " its session");
  groundsim::request_t r{};
  if (m.op == "respawn") {  // a race's respawn: OP_RESET of one vehicle (docs/protocol.md, Race events)
    if (ps.vehicle < 0) return browsers_.refuse(p, m.op, "", "no car to respawn");
    r.steps = -1 - ps.vehicle;
  }
  r.op = m.op == "reset" || m.op == "respawn" ? groundsim::request_t::OP_RESET
         : m.op == "pause" ? groundsim::request_t::OP_PAUSE
                           : groundsim::request_t::OP_RESUME;
  r.session_id = ps.session;
  const SessionEntry* s = sessions_.find(ps.session);
  r.token = s ? s->token : std::string();  // "" once stopped: the server's refusal says so
  const std::string op = m.op;
  requests_.send(r, [this, p, op](const groundsim::reply_t* rep) {
    if (!browsers_.attached(p)) return;
    if (!rep) return browsers_.refuse(p, op, "", "no server answered");
    if (!rep->ok) return browsers_.refuse(p, op, "", rep->error);
    Browsers::send(p, json{{"op", "reply"}, {"request", op}, {"ok", true}}.dump());
  });
}

// The ground around (cx, cy) for the page's terrain, sampled on the worker:
// one grid at a time per browser, only the newest request waiting.
void Hub::ground(Peer* p, PeerState& ps, const GroundMsg& m) {
  if (ps.session.empty()) return browsers_.refuse(p, "ground", "", "not in a session (join first)");
  const SessionEntry* s = sessions_.find(ps.session);
  if (!s || !s->view)
    return browsers_.refuse(p, "ground", "",
                            !s || s->view_error.empty() ? "the session's scene is not known yet" : s->view_error);
  if (ps.grid_busy) {
    ps.grid_next = m;
    return;
  }
  ps.grid_busy = true;
  worker_.post([this, p, view = s->view, id = ps.session, m, n = cfg_.grid_n, step = cfg_.grid_step] {
    json grid = groundGrid(*view->ground, m.cx, m.cy, n, step);
    grid["op"] = "ground";
    grid["session"] = id;
    asio::post(io_, [this, p, id, text = shared(grid.dump())] {
      PeerState* ps = browsers_.find(p);
      if (!ps) return;
      ps->grid_busy = false;
      if (ps->session == id) p->send(text);
      if (auto next = ps->grid_next) {
        ps->grid_next.reset();
        ground(p, *ps, *next);
      }
    });
  });
}

// ---- to the watchers ----------------------------------------------------------

void Hub::postToWatchers(const std::string& id, Slot slot, std::shared_ptr<const std::string> json) {
  asio::post(io_, [this, id, slot, json] { toWatchers(id, slot, json); });
}

void Hub::toWatchers(const std::string& id, Slot slot, std::shared_ptr<const std::string> json) {
  if (const SessionEntry* s = sessions_.find(id))
    for (Peer* p : s->watchers) p->sendLatest(slot, json);
}

void Hub::onEvent(const groundsim::event_t& e, std::shared_ptr<const std::string> json) {
  if (e.session_id.empty()) return;
  SessionEntry* s = sessions_.find(e.session_id);
  if (!s) return;
  s->race.note(e.reason, json);
  for (Peer* p : s->watchers) p->send(json);
}

void Hub::tick() {
  creates_.stopOrphans(Clock::now());
  sessions_.prune();  // a hostile browser cannot grow the table
  lobby_.publish();
  ticker_.expires_after(std::chrono::seconds(1));
  ticker_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) tick();
  });
}

}  // namespace groundsim::web
