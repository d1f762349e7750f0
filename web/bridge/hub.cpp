#include "bridge/hub.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <boost/asio/post.hpp>

#include "bridge/state_json.hpp"
#include "lcm/latency_trace.hpp"
#include "protocol/assets_client.hpp"
#include "protocol/names.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::web {

namespace asio = boost::asio;
using nlohmann::json;
using Clock = std::chrono::steady_clock;
// at most one drive command per browser per period (bounds what a browser can make the server do)
constexpr auto kControlsPeriod = std::chrono::milliseconds(4);
constexpr auto kLobbyPeriod = std::chrono::milliseconds(50);

namespace {

std::shared_ptr<const std::string> shared(std::string s) { return std::make_shared<const std::string>(std::move(s)); }

// a browser's mode by its name (protocol/names.hpp); real time when it names none
std::int8_t modeValue(const std::string& m) {
  const int v = net::modeFromName(m);
  return static_cast<std::int8_t>(v != 0 ? v : groundsim::request_t::MODE_REALTIME);
}

}  // namespace

Hub::Hub(asio::io_context& io, HubConfig cfg, Bus bus) : io_(io), cfg_(std::move(cfg)), bus_(std::move(bus)), ticker_(io), lobby_timer_(io) {
  // every scenario under configs_dir, with its description and how many
  // cars it hosts (shipped_scenarios.hpp), sent to each browser as it connects
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
  tick();
}

Hub::~Hub() {
  ticker_.cancel();
  lobby_timer_.cancel();
}

// ---- LCM thread -------------------------------------------------------------

LcmHandlers Hub::lcmHandlers() {
  LcmHandlers h;
  h.status = [this](const groundsim::server_status_t& s) { asio::post(io_, [this, s] { onStatus(s); }); };
  h.state = [this](const groundsim::state_t& s) {
    const std::string& id = s.session_id;
    if (net::LatencyTrace::on())
      net::LatencyTrace::line("srx %s %lld %lld", id.c_str(), static_cast<long long>(s.seq),
                              static_cast<long long>(net::LatencyTrace::nowUs()));
    bool watched = false;
    {
      std::lock_guard<std::mutex> lk(shared_mu_);
      BusSeen& b = seen_[id];
      b.t = s.t;
      b.nvehicles = s.nvehicles;
      b.last = Clock::now();
      auto it = watched_.find(id);
      watched = it != watched_.end() && it->second > 0;
    }
    if (!watched) return;
    // re-encoded once, shared by every browser watching
    const double wall = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
    auto json = shared(stateJson(s, wall));
    asio::post(io_, [this, id, json] { onState(id, json); });
  };
  h.car_state = [this](const groundsim::car_state_t& s) {
    const std::string& id = s.session_id;
    {
      std::lock_guard<std::mutex> lk(shared_mu_);
      auto it = watched_.find(id);
      if (it == watched_.end() || it->second <= 0) return;
    }
    auto json = shared(carStateJson(s));
    asio::post(io_, [this, id, json] { onCarState(id, json); });
  };
  h.event = [this](const groundsim::event_t& e) {
    auto json = shared(eventJson(e));
    asio::post(io_, [this, e, json] { onEvent(e, json); });
  };
  h.reply = [this](const groundsim::reply_t& r) {
    if (!ours(r.client_id)) return;
    asio::post(io_, [this, r] { onReply(r); });
  };
  h.scenario = [this](const groundsim::scenario_t& s) { asio::post(io_, [this, s] { onScenario(s); }); };
  h.asset_want = [this](const groundsim::asset_want_t& w) {
    if (!ours(w.client_id)) return;
    asio::post(io_, [this, w] {
      if (wants_.size() > 64) wants_.erase(wants_.begin());  // creates long answered
      auto& list = wants_[w.request_id];
      if (list.size() < scenario::kMaxAssets) list.push_back(w);  // a create names at most kMaxAssets files
    });
  };
  h.bad = [this](const std::string& channel, const std::string& reason) {
    ++undecodable_;
    if (cfg_.log) std::fprintf(stderr, "groundsim-web: undecodable message on %s: %s\n", channel.c_str(), reason.c_str());
  };
  return h;
}

// ---- browsers -----------------------------------------------------------------

bool Hub::ours(const std::string& id) const {
  const std::string& me = bus_.client_id;
  return id == me || (id.size() > me.size() + 2 && id.compare(0, me.size(), me) == 0 && id.compare(me.size(), 2, "-b") == 0);
}

void Hub::attach(Peer* p) {
  PeerState& ps = peers_[p];
  ps = PeerState{};
  ps.serial = next_browser_++;
  ps.allowance = std::make_shared<BrowserAllowance>(cfg_.limits);
  p->send(welcome_);
  publishLobby();
  if (cfg_.log) std::fprintf(stderr, "groundsim-web: browser %s connected\n", p->describe().c_str());
}

void Hub::detach(Peer* p) {
  if (!peers_.count(p)) return;
  leave(p);
  peers_.erase(p);
  for (auto& [id, s] : sessions_)
    s.pending.erase(std::remove_if(s.pending.begin(), s.pending.end(), [p](auto& j) { return j.first == p; }),
                    s.pending.end());
  if (cfg_.log) std::fprintf(stderr, "groundsim-web: browser %s disconnected\n", p->describe().c_str());
}

void Hub::sendJson(Peer* p, const std::string& text) { p->send(shared(text)); }

std::size_t Hub::sessionsWatched() const {
  return static_cast<std::size_t>(
      std::count_if(sessions_.begin(), sessions_.end(), [](const auto& s) { return !s.second.watchers.empty(); }));
}

void Hub::refuse(Peer* p, const std::string& op, const std::string& field, const std::string& reason) {
  ++refused_;
  auto it = peers_.find(p);
  if (cfg_.log && it != peers_.end() && it->second.logged < 20) {
    ++it->second.logged;
    std::fprintf(stderr, "groundsim-web: browser %s: refused %s%s%s: %s\n", p->describe().c_str(),
                 op.empty() ? "message" : op.c_str(), field.empty() ? "" : " at ", field.c_str(), reason.c_str());
  }
  sendJson(p, json{{"op", "error"}, {"request", op}, {"field", field}, {"reason", reason}}.dump());
}

void Hub::onBinary(Peer* p) { refuse(p, "", "", "binary messages are not accepted: send JSON text"); }

void Hub::onText(Peer* p, const std::string& text) {
  auto it = peers_.find(p);
  if (it == peers_.end()) return;
  ParsedMessage m = parseBrowserMessage(text);
  if (!m.message) return refuse(p, m.op, m.error.field, m.error.reason);
  try {
    handle(p, it->second, *m.message);
  } catch (const std::exception& e) {
    // nothing a browser sends may take the bridge down
    refuse(p, m.op, "", std::string("internal error: ") + e.what());
  }
}

void Hub::handle(Peer* p, PeerState& ps, const BrowserMessage& m) {
  if (auto* c = std::get_if<ControlsMsg>(&m)) return controls(p, ps, *c);
  if (auto* g = std::get_if<GroundMsg>(&m)) return ground(p, ps, *g);
  if (auto* j = std::get_if<JoinMsg>(&m)) return join(p, *j);
  if (auto* v = std::get_if<PreviewMsg>(&m)) return preview(p, *v);
  if (auto* c = std::get_if<CreateMsg>(&m)) {
    if (!c->player.empty()) ps.player = c->player;
    // a listed scenario, with as many cars as it hosts
    auto sc = scenarios_.find(c->config);
    if (sc == scenarios_.end()) return refuse(p, "create", "/config", "no shipped scenario named \"" + c->config + "\"");
    const ShippedScenario& s = sc->second;
    if (c->vehicles > 0 && (c->vehicles < s.min_cars || c->vehicles > s.max_cars))
      return refuse(p, "create", "/vehicles",
                    c->config + " hosts " + std::to_string(s.min_cars) +
                        (s.max_cars > s.min_cars ? "-" + std::to_string(s.max_cars) : std::string()) + " cars (" +
                        s.limit + "), got " + std::to_string(c->vehicles));
    if ((c->bots >= 0 || c->bot_skill > 0.0) && !s.race)
      return refuse(p, "create", "/bots", c->config + " is not a race: bots drive in races");
    const int players = c->vehicles > 0 ? c->vehicles : s.vehicles - s.bots;
    if (c->bots > 0 && s.grid > 0 && players + c->bots > s.grid)
      return refuse(p, "create", "/bots",
                    c->config + "'s grid has " + std::to_string(s.grid) + " slots: " + std::to_string(players) +
                        " players leave room for " + std::to_string(std::max(0, s.grid - players)) + " bots, got " +
                        std::to_string(c->bots));
    if (!allowCreate(p, ps, *c, s)) return;
    return create(p, ps, *c, s);
  }
  if (auto* o = std::get_if<SessionOpMsg>(&m)) return sessionOp(p, ps, *o);
  if (std::get_if<LeaveMsg>(&m)) {
    leave(p);
    return sendJson(p, R"({"op":"left"})");
  }
  if (auto* ping = std::get_if<PingMsg>(&m)) {
    const PeerStats st = p->stats();
    char b[256];
    std::snprintf(b, sizeof b,
                  "{\"op\":\"pong\",\"t\":%.17g,\"states_sent\":%llu,\"states_skipped\":%llu,\"queued\":%zu,"
                  "\"waiting_bytes\":%zu,\"send_buffer\":%d}",
                  ping->t, static_cast<unsigned long long>(st.states_sent),
                  static_cast<unsigned long long>(st.states_skipped), st.queued, st.waiting_bytes, st.send_buffer);
    return sendJson(p, b);
  }
}

// ---- requests to the server -----------------------------------------------

void Hub::request(groundsim::request_t r, std::function<void(const groundsim::reply_t*)> done) {
  if (r.client_id.empty()) r.client_id = bus_.client_id;  // a browser's create names that browser
  r.request_id = next_request_++;
  r.utime = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
  auto timer = std::make_shared<asio::steady_timer>(io_);
  timer->expires_after(std::chrono::milliseconds(static_cast<int>(cfg_.reply_timeout_s * 1000)));
  const std::int64_t id = r.request_id;
  timer->async_wait([this, id](const boost::system::error_code& ec) {
    if (ec) return;
    auto it = pending_.find(id);
    if (it == pending_.end()) return;
    auto done = std::move(it->second.done);
    pending_.erase(it);
    if (done) done(nullptr);
  });
  pending_[id] = Pending{std::move(done), timer};
  bus_.request(r);
}

void Hub::onReply(const groundsim::reply_t& r) {
  auto it = pending_.find(r.request_id);
  if (it == pending_.end()) return;
  auto done = std::move(it->second.done);
  it->second.timer->cancel();
  pending_.erase(it);
  if (done) done(&r);
}

int Hub::ownedBy(std::uint64_t serial) const {
  int n = 0;
  for (const auto& [id, s] : sessions_) n += s.creator == serial && !s.token.empty();
  return n;
}

bool Hub::allowCreate(Peer* p, PeerState& ps, const CreateMsg& c, const ShippedScenario& s) {
  if (cfg_.limits.sessions > 0 && ownedBy(ps.serial) + ps.creating >= cfg_.limits.sessions) {
    // what it left behind would end within --orphan-stop anyway
    for (auto& [id, e] : sessions_)
      if (e.creator == ps.serial && !e.token.empty() && e.watchers.empty()) stopSession(id, e);
  }
  const int cars = c.vehicles > 0 ? c.vehicles : s.vehicles;
  const std::optional<Refusal> no = ps.allowance->create(cfg_.limits, c.mode, cars, c.publish_rate,
                                                         ownedBy(ps.serial) + ps.creating, Clock::now());
  if (no) refuse(p, "create", no->field, no->reason);
  return !no;
}

groundsim::request_t Hub::stopRequest(const std::string& id, const std::string& token) const {
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_STOP;
  r.session_id = id;
  r.token = token;
  return r;
}

void Hub::stopSession(const std::string& id, SessionEntry& s) {
  request(stopRequest(id, s.token), nullptr);
  s.token.clear();
  s.unwatched_since = {};
}

void Hub::create(Peer* p, PeerState& ps, const CreateMsg& m, const ShippedScenario& sc) {
  if (std::find(configs_.begin(), configs_.end(), m.config) == configs_.end())
    return refuse(p, "create", "/config", "no shipped scenario named \"" + m.config + "\"");
  const std::filesystem::path file = std::filesystem::path(cfg_.configs_dir) / m.config;
  std::ifstream f(file);
  std::stringstream text;
  text << f.rdbuf();
  std::string doc = text.str();
  if (m.bots >= 0 || m.bot_skill > 0.0) {
    try {
      doc = withBots(doc, m.bots, m.bot_skill);
    } catch (const scenario::ScenarioError& e) {
      return refuse(p, "create", "/bots", e.lines("; "));
    }
  }
  if (m.vehicles > 0) {
    try {
      doc = withVehicles(doc, m.vehicles, cfg_.vehicle_margin);
    } catch (const std::exception& e) {
      return refuse(p, "create", "/vehicles", std::string("cannot copy this scenario's vehicle: ") + e.what());
    }
  }
  // the files it names go with it, read next to it (docs/protocol.md, Assets)
  net::ScenarioWithAssets sent;
  try {
    sent = net::withAssets(doc, file.parent_path().string());
  } catch (const scenario::ScenarioError& e) {
    return refuse(p, "create", "/config", m.config + ": " + e.lines("; "));
  }
  for (const scenario::Asset& a : sent.assets) asset_bytes_[a.ref.sha256] = a.bytes;
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_CREATE;
  r.scenario_json = std::move(sent.json);
  r.mode = modeValue(m.mode);
  r.publish_rate = publishRateFor(cfg_.limits, m.publish_rate, sc.output_rate);
  r.duration = -1;  // a game runs until its players leave
  // the server counts each browser's sessions and creates on its own (--client-sessions, --client-creates)
  r.client_id = bus_.client_id + "-b" + std::to_string(ps.serial);  // a principal of its own (protocol/client_id.hpp)
  ++ps.creating;
  createRound(p, ps.serial, std::move(r),
              std::make_shared<const std::vector<scenario::Asset>>(std::move(sent.assets)), m.drive, 0);
}

void Hub::createRound(Peer* p, std::uint64_t serial, groundsim::request_t r,
                      std::shared_ptr<const std::vector<scenario::Asset>> assets, bool drive, int round) {
  const std::string doc = r.scenario_json;
  request(r, [this, p, serial, drive, doc, r, assets, round](const groundsim::reply_t* rep) {
    // the browser may have gone (and another taken its address): known by its serial
    auto pit = peers_.find(p);
    const bool here = pit != peers_.end() && pit->second.serial == serial;
    const bool again = rep && !rep->ok && rep->error_code == groundsim::asset_want_t::ERR_MISSING_ASSETS &&
                       !assets->empty() && round + 1 < net::kAssetRounds && here;
    if (here && !again) --pit->second.creating;
    if (rep && rep->ok) return created(here ? p : nullptr, serial, *rep, doc, drive);
    if (!here) return;
    if (!rep) return refuse(p, "create", "", "no server answered (is groundsim-server running on this LCM URL?)");
    if (again) {
      std::vector<groundsim::asset_want_t> wants;
      if (auto w = wants_.find(rep->request_id); w != wants_.end()) {
        wants = std::move(w->second);
        wants_.erase(w);
      }
      // a large file takes a while to send: not on the I/O thread
      worker_.post([this, p, serial, r, assets, drive, round, wants] {
        std::string error;
        try {
          if (bus_.assets) bus_.assets(*assets, wants);
        } catch (const std::exception& e) {
          error = std::string("sending the scenario's files: ") + e.what();
        }
        asio::post(io_, [this, p, serial, r, assets, drive, round, error] {
          auto pit = peers_.find(p);
          if (pit == peers_.end() || pit->second.serial != serial) return;
          if (!error.empty()) {
            --pit->second.creating;
            return refuse(p, "create", "", error);
          }
          createRound(p, serial, r, assets, drive, round + 1);
        });
      });
      return;
    }
    return refuse(p, "create", "", rep->error);
  });
}

void Hub::created(Peer* p, std::uint64_t serial, const groundsim::reply_t& rep, const std::string& doc, bool drive) {
  SessionEntry& s = sessions_[rep.session_id];
  s.token = rep.token;  // kept here: never sent to a browser
  s.creator = serial;
  s.unwatched_since = Clock::now();  // until someone watches: a create nobody joins ends too
  scenario_texts_[rep.session_id] = doc;
  if (!p) return;  // its browser left before the reply: ended by tick() as nobody watches it
  sendJson(p, json{{"op", "created"}, {"session", rep.session_id}}.dump());
  JoinMsg j;
  j.session = rep.session_id;
  j.role = drive ? Role::Drive : Role::Spectate;
  join(p, j);
}

scenario::FileAccess Hub::knownAssets(const std::string& scenario_json) const {
  auto bytes = std::make_shared<scenario::AssetBytes>();
  try {
    const json doc = scenario::parseScenarioDocument(scenario_json);
    for (const scenario::AssetRef& ref : scenario::assetManifest(doc))
      if (auto it = asset_bytes_.find(ref.sha256); it != asset_bytes_.end()) (*bytes)[ref.name] = it->second;
  } catch (const std::exception&) {
    // the view's own parse reports what is wrong with the document
  }
  return scenario::FileAccess::fromAssets(std::move(bytes));
}

// ---- joining a session -------------------------------------------------------

void Hub::join(Peer* p, const JoinMsg& m) {
  auto known = sessions_.find(m.session);
  if (m.role == Role::Drive && (known == sessions_.end() || known->second.token.empty()))
    return refuse(p, "join", "/role",
                  "this bridge holds no token for session " + m.session +
                      ": it drives only sessions created through it (spectate instead)");
  leave(p);
  SessionEntry& s = sessions_[m.session];
  s.pending.emplace_back(p, m);
  PeerState& ps = peers_[p];
  if (!m.player.empty()) ps.player = m.player;
  ps.session = m.session;
  ps.role = Role::Spectate;
  ps.vehicle = -1;
  s.watchers.insert(p);
  updateWatched(m.session);
  ensureView(m.session);
}

void Hub::ensureView(const std::string& id) {
  SessionEntry& s = sessions_[id];
  if (s.view || s.view_failed) {
    auto pending = std::move(s.pending);
    s.pending.clear();
    for (auto& [p, m] : pending) finishJoin(p, m);
    return;
  }
  if (s.building) return;
  auto text = scenario_texts_.find(id);
  if (text != scenario_texts_.end()) {
    s.building = true;
    std::string doc = text->second;
    const scenario::FileAccess files = knownAssets(doc);
    worker_.post([this, id, doc, files] {
      std::shared_ptr<SceneView> view;
      std::string error;
      try {
        view = makeSceneView(doc, files);
      } catch (const std::exception& e) {
        error = e.what();
      }
      asio::post(io_, [this, id, view, error] {
        SessionEntry& s = sessions_[id];
        s.building = false;
        s.view = view;
        if (view) {
          s.joined_layout = shared(view->layout.dump());
          if (s.drivers.size() < view->wheels.size()) s.drivers.resize(view->wheels.size(), nullptr);
        } else {
          s.view_failed = true;
          s.view_error = "the session's scenario does not build here: " + error;
        }
        ensureView(id);
      });
    });
    return;
  }
  if (s.fetching) return;
  s.fetching = true;
  groundsim::request_t r{};
  r.op = kOpScenario;
  r.session_id = id;
  request(r, [this, id](const groundsim::reply_t* rep) {
    SessionEntry& s = sessions_[id];
    s.fetching = false;
    if (scenario_texts_.count(id)) return ensureView(id);
    // a replayed session has no server to ask: draw it without its ground
    s.view_failed = true;
    s.view_error = !rep ? "no server knows this session's scenario (a replay?): its ground is not drawn"
                        : "the server did not send the scenario: " + rep->error;
    ensureView(id);
  });
}

void Hub::onScenario(const groundsim::scenario_t& m) {
  if (!validSessionId(m.session_id)) return;
  scenario_texts_[m.session_id] = m.scenario_json;
  auto it = sessions_.find(m.session_id);
  if (it != sessions_.end() && !it->second.pending.empty()) {
    it->second.view_failed = false;
    ensureView(m.session_id);
  }
}

void Hub::finishJoin(Peer* p, const JoinMsg& m) {
  auto pit = peers_.find(p);
  if (pit == peers_.end() || pit->second.session != m.session) return;
  PeerState& ps = pit->second;
  SessionEntry& s = sessions_[m.session];
  if (m.role == Role::Drive) {
    if (!s.view) return refuse(p, "join", "/session", s.view_error);
    int v = m.vehicle;
    if (v >= static_cast<int>(s.drivers.size()))
      return refuse(p, "join", "/vehicle",
                    "session " + m.session + " has " + std::to_string(s.drivers.size()) + " vehicles, got " +
                        std::to_string(v));
    if (v < 0) {
      auto free = std::find(s.drivers.begin(), s.drivers.end(), nullptr);
      if (free == s.drivers.end())
        return refuse(p, "join", "/role", "every vehicle of session " + m.session + " has a driver (spectate instead)");
      v = static_cast<int>(free - s.drivers.begin());
    } else if (s.drivers[v] && s.drivers[v] != p) {
      return refuse(p, "join", "/vehicle", "vehicle " + std::to_string(v) + " already has a driver");
    }
    s.drivers[v] = p;
    ps.role = Role::Drive;
    ps.vehicle = v;
  }
  std::string msg = "{\"op\":\"joined\",\"session\":" + quoted(m.session) +
                    ",\"role\":" + (ps.role == Role::Drive ? "\"drive\"" : "\"spectate\"") +
                    ",\"vehicle\":" + std::to_string(ps.vehicle) + ",\"note\":" + quoted(s.view ? "" : s.view_error) +
                    ",\"layout\":" + (s.joined_layout ? *s.joined_layout : std::string("null"));
  // a driver's page runs the scenario itself to predict its car (web/src/predict.js)
  const auto text = ps.role == Role::Drive ? scenario_texts_.find(m.session) : scenario_texts_.end();
  const std::string& doc = text != scenario_texts_.end() ? text->second : std::string();
  msg += ",\"scenario\":" + (doc.empty() ? std::string("null") : quoted(doc)) + ",\"scale\":{\"drive_torque\":" +
         std::to_string(cfg_.scale.drive_torque) + ",\"brake_torque\":" + std::to_string(cfg_.scale.brake_torque) +
         ",\"steer\":" + std::to_string(cfg_.scale.steer) + "}}";
  sendJson(p, msg);
  for (const auto& race : s.race.catchUp()) p->send(race);  // a race under way: its layout and standings
  publishLobby();
}

void Hub::leave(Peer* p) {
  auto it = peers_.find(p);
  if (it == peers_.end() || it->second.session.empty()) return;
  PeerState& ps = it->second;
  auto sit = sessions_.find(ps.session);
  if (sit != sessions_.end()) {
    SessionEntry& s = sit->second;
    s.watchers.erase(p);
    for (auto& d : s.drivers)
      if (d == p) d = nullptr;
    if (ps.role == Role::Drive && !s.token.empty() && s.view && ps.vehicle >= 0) {
      // release the car's controls rather than leaving its last command held
      sendControls(s, ps.session, ps.vehicle, Controls{0, 0, 0, false, 0}, 0);
    }
    if (s.watchers.empty()) s.unwatched_since = Clock::now();
  }
  const std::string id = ps.session;
  // what is the browser's, not its session's, stays: who it is, its name, its allowance
  PeerState kept;
  kept.serial = ps.serial;
  kept.allowance = std::move(ps.allowance);
  kept.creating = ps.creating;
  kept.logged = ps.logged;
  kept.player = std::move(ps.player);
  ps = std::move(kept);
  updateWatched(id);
  publishLobby();
}

void Hub::updateWatched(const std::string& id) {
  auto it = sessions_.find(id);
  const int n = it == sessions_.end() ? 0 : static_cast<int>(it->second.watchers.size());
  std::lock_guard<std::mutex> lk(shared_mu_);
  if (n) watched_[id] = n; else watched_.erase(id);
}

// ---- playing ---------------------------------------------------------------------

void Hub::controls(Peer* p, PeerState& ps, const ControlsMsg& m) {
  if (ps.role != Role::Drive) return refuse(p, "controls", "", "not driving a vehicle (join with role drive first)");
  // A browser cannot flood the server: at most one command per period each.
  // One that comes sooner is held, the newest replacing an older, and sent
  // when the period is over. Dropped instead, a key press or release that
  // came right after the page's periodic re-send (or in a burst after a
  // stall) would wait for the next re-send, 50 ms on.
  const auto now = Clock::now();
  const auto due = ps.last_drive + kControlsPeriod;
  if (now >= due) return driveNow(ps, m, now);
  if (ps.held && net::LatencyTrace::on())
    net::LatencyTrace::line("ctl %s %.0f -1 %lld -1", ps.session.c_str(), ps.held->seq,
                            static_cast<long long>(net::LatencyTrace::us(ps.held_rx)));
  const bool waiting = ps.held.has_value();
  ps.held = m;
  ps.held_rx = now;
  if (waiting) return;
  if (!ps.hold_timer) ps.hold_timer = std::make_shared<asio::steady_timer>(io_);
  ps.hold_timer->expires_at(due);
  ps.hold_timer->async_wait([this, p, timer = std::weak_ptr(ps.hold_timer)](const boost::system::error_code& ec) {
    if (!ec) sendHeld(p, timer);
  });
}

// The held controls of a browser, if it still drives: its PeerState (and
// the timer it owns) is gone when it left or disconnected.
void Hub::sendHeld(Peer* p, const std::weak_ptr<asio::steady_timer>& timer) {
  const auto t = timer.lock();
  auto it = peers_.find(p);
  if (!t || it == peers_.end() || it->second.hold_timer != t || !it->second.held) return;
  PeerState& ps = it->second;
  const ControlsMsg m = *ps.held;
  ps.held.reset();
  if (ps.role == Role::Drive) driveNow(ps, m, ps.held_rx);
}

void Hub::driveNow(PeerState& ps, const ControlsMsg& m, Clock::time_point rx) {
  ps.last_drive = Clock::now();
  const std::int64_t seq = ps.drive_seq++;
  sendControls(sessions_[ps.session], ps.session, ps.vehicle, m.controls, seq);
  if (net::LatencyTrace::on())
    net::LatencyTrace::line("ctl %s %.0f %lld %lld %lld", ps.session.c_str(), m.seq, static_cast<long long>(seq),
                            static_cast<long long>(net::LatencyTrace::us(rx)),
                            static_cast<long long>(net::LatencyTrace::nowUs()));
}

void Hub::sendControls(const SessionEntry& s, const std::string& session, int vehicle, const Controls& c,
                       std::int64_t seq) {
  const auto utime =
      std::chrono::duration_cast<std::chrono::microseconds>(Clock::now().time_since_epoch()).count();
  const bool road_car = static_cast<size_t>(vehicle) < s.view->road_car.size() && s.view->road_car[vehicle];
  if (road_car) {
    groundsim::controls_t m = toCarControls(c, vehicle);
    m.utime = utime;
    m.seq = seq;
    m.client_id = bus_.client_id;
    m.session_id = session;
    m.token = s.token;
    if (bus_.controls) bus_.controls(m);
    return;
  }
  groundsim::drive_t d = toDrive(c, vehicle, s.view->wheels[vehicle], cfg_.scale);
  d.utime = utime;
  d.seq = seq;
  d.client_id = bus_.client_id;
  d.session_id = session;
  d.token = s.token;
  bus_.drive(d);
}

void Hub::sessionOp(Peer* p, PeerState& ps, const SessionOpMsg& m) {
  if (ps.role != Role::Drive) return refuse(p, m.op, "", "only a driver may " + m.op + " its session");
  groundsim::request_t r{};
  if (m.op == "respawn") {  // a race's respawn: OP_RESET of one vehicle (docs/protocol.md, Race events)
    if (ps.vehicle < 0) return refuse(p, m.op, "", "no car to respawn");
    r.steps = -1 - ps.vehicle;
  }
  r.op = m.op == "reset" || m.op == "respawn" ? groundsim::request_t::OP_RESET
         : m.op == "pause" ? groundsim::request_t::OP_PAUSE
                           : groundsim::request_t::OP_RESUME;
  r.session_id = ps.session;
  r.token = sessions_[ps.session].token;
  const std::string op = m.op;
  request(r, [this, p, op](const groundsim::reply_t* rep) {
    if (!peers_.count(p)) return;
    if (!rep) return refuse(p, op, "", "no server answered");
    if (!rep->ok) return refuse(p, op, "", rep->error);
    sendJson(p, json{{"op", "reply"}, {"request", op}, {"ok", true}}.dump());
  });
}

void Hub::preview(Peer* p, const PreviewMsg& m) {
  if (!scenarios_.count(m.config)) return refuse(p, "preview", "/config", "no shipped scenario named \"" + m.config + "\"");
  if (auto it = previews_.find(m.config); it != previews_.end()) return p->send(it->second);
  auto& waiting = preview_waiting_[m.config];
  if (std::find(waiting.begin(), waiting.end(), p) == waiting.end()) waiting.push_back(p);
  if (waiting.size() > 1) return;  // queued or under way
  preview_queue_.push_back(m.config);
  nextPreview();
}

void Hub::nextPreview() {
  if (preview_busy_ || preview_queue_.empty()) return;
  preview_busy_ = true;
  const std::string id = preview_queue_.front(), dir = cfg_.configs_dir;
  preview_queue_.pop_front();
  worker_.post([this, id, dir] {
    const auto t0 = Clock::now();
    json out;
    try {
      out = scenarioPreview(dir, id);
    } catch (const std::exception& e) {
      out = {{"error", e.what()}};
    }
    out["op"] = "preview";
    out["config"] = id;
    out["ms"] = std::round(std::chrono::duration<double, std::milli>(Clock::now() - t0).count() * 10.0) / 10.0;
    auto text = shared(out.dump());
    asio::post(io_, [this, id, text] {
      previews_[id] = text;
      auto waiting = std::move(preview_waiting_[id]);
      preview_waiting_.erase(id);
      for (Peer* q : waiting)
        if (peers_.count(q)) q->send(text);
      preview_busy_ = false;
      nextPreview();
    });
  });
}

void Hub::ground(Peer* p, PeerState& ps, const GroundMsg& m) {
  if (ps.session.empty()) return refuse(p, "ground", "", "not in a session (join first)");
  SessionEntry& s = sessions_[ps.session];
  if (!s.view) return refuse(p, "ground", "", s.view_error.empty() ? "the session's scene is not known yet" : s.view_error);
  if (ps.grid_busy) {
    ps.grid_next = m;  // only the newest request waiting
    return;
  }
  ps.grid_busy = true;
  auto view = s.view;
  const std::string id = ps.session;
  const int n = cfg_.grid_n;
  const double step = cfg_.grid_step;
  worker_.post([this, p, view, id, m, n, step] {
    json grid = groundGrid(*view->ground, m.cx, m.cy, n, step);
    grid["op"] = "ground";
    grid["session"] = id;
    auto text = shared(grid.dump());
    asio::post(io_, [this, p, id, text] {
      auto it = peers_.find(p);
      if (it == peers_.end()) return;
      it->second.grid_busy = false;
      if (it->second.session == id) p->send(text);
      if (auto next = it->second.grid_next) {
        it->second.grid_next.reset();
        ground(p, it->second, *next);
      }
    });
  });
}

// ---- from the server -------------------------------------------------------------

void Hub::onState(const std::string& id, std::shared_ptr<const std::string> json) {
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return;
  for (Peer* p : it->second.watchers) p->sendLatest(Slot::State, json);
}

void Hub::onCarState(const std::string& id, std::shared_ptr<const std::string> json) {
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return;
  for (Peer* p : it->second.watchers) p->sendLatest(Slot::Car, json);
}

bool Hub::watched(const std::string& id) {
  std::lock_guard<std::mutex> lk(shared_mu_);
  auto it = watched_.find(id);
  return it != watched_.end() && it->second > 0;
}

void Hub::postToWatchers(const std::string& id, Slot slot, std::shared_ptr<const std::string> json) {
  asio::post(io_, [this, id, slot, json] {
    auto it = sessions_.find(id);
    if (it == sessions_.end()) return;
    for (Peer* p : it->second.watchers) p->sendLatest(slot, json);
  });
}

void Hub::onEvent(const groundsim::event_t& e, std::shared_ptr<const std::string> json) {
  if (e.session_id.empty()) return;
  auto it = sessions_.find(e.session_id);
  if (it == sessions_.end()) return;
  it->second.race.note(e.reason, json);
  for (Peer* p : it->second.watchers) p->send(json);
}

void Hub::onStatus(const groundsim::server_status_t& s) {
  status_ = s;
  status_time_ = Clock::now();
  have_status_ = true;
  publishLobby();
}

void Hub::tick() {
  const auto now = Clock::now();
  for (auto& [id, s] : sessions_) {
    if (s.token.empty() || !s.watchers.empty() || s.unwatched_since == Clock::time_point{}) continue;
    if (now - s.unwatched_since < std::chrono::milliseconds(static_cast<int>(cfg_.orphan_stop_s * 1000))) continue;
    stopSession(id, s);
  }
  // forget views of sessions nobody watches (a hostile browser cannot grow the table)
  for (auto it = sessions_.begin(); it != sessions_.end();) {
    const SessionEntry& s = it->second;
    if (s.token.empty() && s.watchers.empty() && s.pending.empty() && !s.building && !s.fetching)
      it = sessions_.erase(it);
    else
      ++it;
  }
  publishLobby();
  ticker_.expires_after(std::chrono::seconds(1));
  ticker_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) tick();
  });
}

void Hub::stopOwnedSessions() {
  for (auto& [id, s] : sessions_) {
    if (s.token.empty()) continue;
    // not through request(): the I/O loop that would time its reply out is ending
    groundsim::request_t r = stopRequest(id, s.token);
    r.client_id = bus_.client_id;
    r.request_id = next_request_++;
    bus_.request(r);
    s.token.clear();
  }
}

// At most one lobby every kLobbyPeriod: joins, leaves and connections (a
// page can cause hundreds a second) publish it at once when the last is
// older than that (so it reaches a page before the answer that caused it),
// else mark it due for one timer that builds it once for every browser.
void Hub::publishLobby() {
  if (lobby_due_) return;
  const auto now = Clock::now();
  if (now - lobby_sent_ >= kLobbyPeriod) return publishLobbyNow();
  lobby_due_ = true;
  lobby_timer_.expires_at(lobby_sent_ + kLobbyPeriod);
  lobby_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    lobby_due_ = false;
    publishLobbyNow();
  });
}

void Hub::publishLobbyNow() {
  const auto now = Clock::now();
  lobby_sent_ = now;
  json sessions = json::array();
  std::set<std::string> listed;
  auto entry = [&](const std::string& id) -> json {
    json j;
    auto it = sessions_.find(id);
    int drivers = 0, free = 0, watchers = 0;
    bool owned = false, unsized = true;
    // who is in: a name per vehicle (null: free, "": a driver who gave none)
    // and the spectators' names
    json players = json::array(), spectators = json::array();
    auto nameOf = [&](Peer* q) {
      auto pq = peers_.find(q);
      return pq == peers_.end() ? std::string() : pq->second.player;
    };
    if (it != sessions_.end()) {
      unsized = it->second.drivers.empty();
      owned = !it->second.token.empty();
      watchers = static_cast<int>(it->second.watchers.size());
      for (Peer* d : it->second.drivers) {
        d ? ++drivers : ++free;
        players.push_back(d ? json(nameOf(d)) : json(nullptr));
      }
      for (Peer* w : it->second.watchers)
        if (std::find(it->second.drivers.begin(), it->second.drivers.end(), w) == it->second.drivers.end())
          spectators.push_back(nameOf(w));
    }
    j["players"] = std::move(players);
    j["spectators"] = std::move(spectators);
    j["drivable"] = owned && (free > 0 || unsized);
    j["free"] = free;
    j["drivers"] = drivers;
    j["watchers"] = watchers;
    return j;
  };
  const bool fresh = have_status_ && now - status_time_ < std::chrono::seconds(3);
  if (fresh) {
    for (const auto& si : status_.sessions) {
      json j = entry(si.session_id);
      j["id"] = si.session_id;
      j["name"] = si.name;
      j["mode"] = net::modeName(si.mode);
      j["status"] = si.status;
      j["reason"] = si.status_reason;
      j["t"] = si.utime * 1e-6;
      j["rate"] = si.rate;
      j["publish_rate"] = si.publish_rate;
      j["vehicles"] = si.vehicle_names;
      j["wheel_counts"] = std::vector<int>(si.wheel_counts.begin(), si.wheel_counts.end());
      j["dt"] = si.dt;
      j["num_envs"] = si.num_envs;  // > 0: a vectorised session (nothing to draw: it publishes no states)
      j["source"] = "server";
      listed.insert(si.session_id);
      sessions.push_back(std::move(j));
    }
  }
  {
    // states on the bus that no heartbeat lists: a replay, or another server's
    std::lock_guard<std::mutex> lk(shared_mu_);
    for (auto it = seen_.begin(); it != seen_.end();) {
      if (now - it->second.last > std::chrono::seconds(5)) {
        it = seen_.erase(it);
        continue;
      }
      if (!listed.count(it->first) && validSessionId(it->first)) {
        json j = entry(it->first);
        j["id"] = it->first;
        j["name"] = "";
        j["mode"] = "unknown";
        j["status"] = 1;
        j["reason"] = "";
        j["t"] = it->second.t;
        j["vehicles"] = json::array();
        j["source"] = "bus";
        sessions.push_back(std::move(j));
      }
      ++it;
    }
  }
  json lobby = {{"op", "lobby"}, {"sessions", sessions}, {"server", nullptr}};
  if (fresh)
    lobby["server"] = {{"id", status_.server_id}, {"workers", status_.workers}, {"load", status_.load},
                       {"sessions", status_.nsessions}, {"errors", status_.errors}};
  auto text = shared(lobby.dump());
  for (auto& [p, ps] : peers_) p->sendLatest(Slot::Lobby, text);
}

}  // namespace groundsim::web
