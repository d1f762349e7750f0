#include "bridge/seats.hpp"

#include <algorithm>

#include <boost/asio/post.hpp>

#include "bridge/hub.hpp"
#include "bridge/lcm_link.hpp"
#include "bridge/state_json.hpp"

namespace groundsim::web {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

Seats::Seats(asio::io_context& io, Worker& worker, const HubConfig& cfg, const Bus& bus, Browsers& browsers,
             SessionTable& sessions, Requests& requests, Lobby& lobby, const Creates& creates)
    : io_(io), worker_(worker), cfg_(cfg), bus_(bus), browsers_(browsers), sessions_(sessions), requests_(requests),
      lobby_(lobby), creates_(creates) {}

void Seats::join(Peer* p, const JoinMsg& m) {
  const SessionEntry* known = sessions_.find(m.session);
  if (m.role == Role::Drive && (!known || !known->owned()))
    return browsers_.refuse(p, "join", "/role",
                            "this bridge holds no token for session " + m.session +
                                ": it drives only sessions created through it (spectate instead)");
  leave(p);
  SessionEntry& s = sessions_.open(m.session);
  s.pending.emplace_back(p, m);
  PeerState* ps = browsers_.find(p);
  if (!ps) return;
  if (!m.player.empty()) ps->player = m.player;
  ps->session = m.session;
  ps->role = Role::Spectate;
  ps->vehicle = -1;
  s.watchers.insert(p);
  sessions_.updateWatched(m.session);
  ensureView(m.session);
}

void Seats::leave(Peer* p) {
  PeerState* ps = browsers_.find(p);
  if (!ps || ps->session.empty()) return;
  if (SessionEntry* s = sessions_.find(ps->session)) {
    s->watchers.erase(p);
    for (auto& d : s->drivers)
      if (d == p) d = nullptr;
    if (ps->role == Role::Drive && s->owned() && s->view && ps->vehicle >= 0) {
      // release the car's controls rather than leaving its last command held
      publishControls(bus_, cfg_.scale, *s, ps->session, ps->vehicle, Controls{0, 0, 0, false, 0}, 0);
    }
    if (s->watchers.empty()) s->unwatched_since = Clock::now();
  }
  const std::string id = ps->session;
  ps->leaveSession();
  sessions_.updateWatched(id);
  lobby_.publish();
}

void Seats::ensureView(const std::string& id) {
  SessionEntry* s = sessions_.find(id);
  if (!s) return;
  if (s->view || s->view_failed) {
    auto pending = std::move(s->pending);
    s->pending.clear();
    for (auto& [p, m] : pending) finishJoin(p, m);
    return;
  }
  if (s->building) return;
  if (const std::string* doc = sessions_.scenario(id)) return buildView(id, *s, *doc);
  if (!s->fetching) fetchScenario(id, *s);
}

void Seats::buildView(const std::string& id, SessionEntry& s, const std::string& doc) {
  s.building = true;
  const scenario::FileAccess files = creates_.knownAssets(doc);
  worker_.post([this, id, doc, files] {
    std::shared_ptr<SceneView> view;
    std::string error;
    try {
      view = makeSceneView(doc, files);
    } catch (const std::exception& e) {
      error = e.what();
    }
    asio::post(io_, [this, id, view, error] {
      SessionEntry& s = sessions_.open(id);  // kept while building (SessionEntry::idle)
      s.building = false;
      s.view = view;
      if (view) {
        s.joined_layout = std::make_shared<const std::string>(view->layout.dump());
        if (s.drivers.size() < view->wheels.size()) s.drivers.resize(view->wheels.size(), nullptr);
      } else {
        s.view_failed = true;
        s.view_error = "the session's scenario does not build here: " + error;
      }
      ensureView(id);
    });
  });
}

void Seats::fetchScenario(const std::string& id, SessionEntry& s) {
  s.fetching = true;
  groundsim::request_t r{};
  r.op = kOpScenario;
  r.session_id = id;
  requests_.send(r, [this, id](const groundsim::reply_t* rep) {
    SessionEntry& s = sessions_.open(id);  // kept while fetching (SessionEntry::idle)
    s.fetching = false;
    if (sessions_.scenario(id)) return ensureView(id);
    // a replayed session has no server to ask: draw it without its ground
    s.view_failed = true;
    s.view_error = !rep ? "no server knows this session's scenario (a replay?): its ground is not drawn"
                        : "the server did not send the scenario: " + rep->error;
    ensureView(id);
  });
}

void Seats::onScenario(const groundsim::scenario_t& m) {
  if (!validSessionId(m.session_id)) return;
  sessions_.setScenario(m.session_id, m.scenario_json);
  SessionEntry* s = sessions_.find(m.session_id);
  if (s && !s->pending.empty()) {
    s->view_failed = false;
    ensureView(m.session_id);
  }
}

void Seats::finishJoin(Peer* p, const JoinMsg& m) {
  PeerState* ps = browsers_.find(p);
  SessionEntry* s = sessions_.find(m.session);
  if (!ps || !s || ps->session != m.session) return;
  if (m.role == Role::Drive) {
    const int v = seatDriver(p, m, *s);
    if (v < 0) return;
    ps->role = Role::Drive;
    ps->vehicle = v;
    ps->throttle = std::make_unique<ControlsThrottle>(
        io_, m.session, [this, p](const ControlsMsg& c, std::int64_t seq, Clock::time_point) {
          const PeerState* d = browsers_.find(p);
          const SessionEntry* e = d ? sessions_.find(d->session) : nullptr;
          if (d && e && d->role == Role::Drive) publishControls(bus_, cfg_.scale, *e, d->session, d->vehicle, c.controls, seq);
        });
  }
  Browsers::send(p, joinedMessage(*ps, m.session, *s));
  for (const auto& race : s->race.catchUp()) p->send(race);  // a race under way: its layout and standings
  lobby_.publish();
}

int Seats::seatDriver(Peer* p, const JoinMsg& m, SessionEntry& s) {
  if (!s.view) return browsers_.refuse(p, "join", "/session", s.view_error), -1;
  int v = m.vehicle;
  if (v >= static_cast<int>(s.drivers.size()))
    return browsers_.refuse(p, "join", "/vehicle",
                            "session " + m.session + " has " + std::to_string(s.drivers.size()) + " vehicles, got " +
                                std::to_string(v)),
           -1;
  if (v < 0) {
    auto free = std::find(s.drivers.begin(), s.drivers.end(), nullptr);
    if (free == s.drivers.end())
      return browsers_.refuse(p, "join", "/role",
                              "every vehicle of session " + m.session + " has a driver (spectate instead)"),
             -1;
    v = static_cast<int>(free - s.drivers.begin());
  } else if (s.drivers[v] && s.drivers[v] != p) {
    return browsers_.refuse(p, "join", "/vehicle", "vehicle " + std::to_string(v) + " already has a driver"), -1;
  }
  s.drivers[v] = p;
  return v;
}

std::string Seats::joinedMessage(const PeerState& ps, const std::string& session, const SessionEntry& s) const {
  std::string msg = "{\"op\":\"joined\",\"session\":" + quoted(session) +
                    ",\"role\":" + (ps.role == Role::Drive ? "\"drive\"" : "\"spectate\"") +
                    ",\"vehicle\":" + std::to_string(ps.vehicle) + ",\"note\":" + quoted(s.view ? "" : s.view_error) +
                    ",\"layout\":" + (s.joined_layout ? *s.joined_layout : std::string("null"));
  // a driver's page runs the scenario itself to predict its car (web/src/predict.js)
  const std::string* doc = ps.role == Role::Drive ? sessions_.scenario(session) : nullptr;
  msg += ",\"scenario\":" + (doc && !doc->empty() ? quoted(*doc) : std::string("null")) +
         ",\"scale\":{\"drive_torque\":" + std::to_string(cfg_.scale.drive_torque) +
         ",\"brake_torque\":" + std::to_string(cfg_.scale.brake_torque) +
         ",\"steer\":" + std::to_string(cfg_.scale.steer) + "}}";
  return msg;
}

}  // namespace groundsim::web
