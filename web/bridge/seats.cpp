#include "bridge/seats.hpp"

#include <algorithm>

#include <boost/asio/post.hpp>

#include "bridge/hub.hpp"
#include "bridge/lcm_link.hpp"
#include "bridge/state_json.hpp"

namespace groundsim::web {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

Seats::Seats(const HubContext& c, Lobby& lobby, const Creates& creates) : c_(c), lobby_(lobby), creates_(creates) {}

void Seats::join(Peer* p, const JoinMsg& m) {
  const SessionEntry* known = c_.sessions.find(m.session);
  if (m.role == Role::Drive && (!known || !known->owned()))
    return c_.browsers.refuse(p, "join", "/role",
                            "this bridge holds no token for session " + m.session +
                                ": it drives only sessions created through it (spectate instead)");
  leave(p);
  SessionEntry& s = c_.sessions.open(m.session);
  s.pending.emplace_back(p, m);
  PeerState* ps = c_.browsers.find(p);
  if (!ps) return;
  if (!m.player.empty()) ps->player = m.player;
  ps->session = m.session;
  ps->role = Role::Spectate;
  ps->vehicle = -1;
  s.watchers.insert(p);
  c_.sessions.updateWatched(m.session);
  ensureView(m.session);
}

void Seats::leave(Peer* p) {
  PeerState* ps = c_.browsers.find(p);
  if (!ps || ps->session.empty()) return;
  if (SessionEntry* s = c_.sessions.find(ps->session)) {
    s->watchers.erase(p);
    for (auto& d : s->drivers)
      if (d == p) d = nullptr;
    if (ps->role == Role::Drive && s->owned() && s->view && ps->vehicle >= 0) {
      // release the car's controls rather than leaving its last command held
      publishControls(c_.bus, c_.cfg.scale, *s, ps->session, ps->vehicle, Controls{0, 0, 0, false, 0}, 0);
    }
    if (s->watchers.empty()) s->unwatched_since = Clock::now();
  }
  const std::string id = ps->session;
  ps->leaveSession();
  c_.sessions.updateWatched(id);
  lobby_.publish();
}

void Seats::ensureView(const std::string& id) {
  SessionEntry* s = c_.sessions.find(id);
  if (!s) return;
  if (s->view || s->view_failed) {
    auto pending = std::move(s->pending);
    s->pending.clear();
    for (auto& [p, m] : pending) finishJoin(p, m);
    return;
  }
  if (s->building) return;
  if (const std::string* doc = c_.sessions.scenario(id)) return buildView(id, *s, *doc);
  if (!s->fetching) fetchScenario(id, *s);
}

void Seats::buildView(const std::string& id, SessionEntry& s, const std::string& doc) {
  s.building = true;
  const scenario::FileAccess files = creates_.knownAssets(doc);
  c_.worker.post([this, id, doc, files] {
    std::shared_ptr<SceneView> view;
    std::string error;
    try {
      view = makeSceneView(doc, files);
    } catch (const std::exception& e) {
      error = e.what();
    }
    asio::post(c_.io, [this, id, view, error] {
      SessionEntry& s = c_.sessions.open(id);  // kept while building (SessionEntry::idle)
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
  c_.requests.send(r, [this, id](const groundsim::reply_t* rep) {
    SessionEntry& s = c_.sessions.open(id);  // kept while fetching (SessionEntry::idle)
    s.fetching = false;
    if (c_.sessions.scenario(id)) return ensureView(id);
    // a replayed session has no server to ask: draw it without its ground
    s.view_failed = true;
    s.view_error = !rep ? "no server knows this session's scenario (a replay?): its ground is not drawn"
                        : "the server did not send the scenario: " + rep->error;
    ensureView(id);
  });
}

void Seats::onScenario(const groundsim::scenario_t& m) {
  if (!validSessionId(m.session_id)) return;
  c_.sessions.setScenario(m.session_id, m.scenario_json);
  SessionEntry* s = c_.sessions.find(m.session_id);
  if (s && !s->pending.empty()) {
    s->view_failed = false;
    ensureView(m.session_id);
  }
}

void Seats::finishJoin(Peer* p, const JoinMsg& m) {
  PeerState* ps = c_.browsers.find(p);
  SessionEntry* s = c_.sessions.find(m.session);
  if (!ps || !s || ps->session != m.session) return;
  if (m.role == Role::Drive) {
    const int v = seatDriver(p, m, *s);
    if (v < 0) return;
    ps->role = Role::Drive;
    ps->vehicle = v;
    ps->throttle = std::make_unique<ControlsThrottle>(
        c_.io, m.session, [this, p](const ControlsMsg& c, std::int64_t seq, Clock::time_point) {
          const PeerState* d = c_.browsers.find(p);
          const SessionEntry* e = d ? c_.sessions.find(d->session) : nullptr;
          if (d && e && d->role == Role::Drive) publishControls(c_.bus, c_.cfg.scale, *e, d->session, d->vehicle, c.controls, seq);
        });
  }
  Browsers::send(p, joinedMessage(*ps, m.session, *s));
  for (const auto& race : s->race.catchUp()) p->send(race);  // a race under way: its layout and standings
  lobby_.publish();
}

int Seats::seatDriver(Peer* p, const JoinMsg& m, SessionEntry& s) {
  if (!s.view) return c_.browsers.refuse(p, "join", "/session", s.view_error), -1;
  int v = m.vehicle;
  if (v >= static_cast<int>(s.drivers.size()))
    return c_.browsers.refuse(p, "join", "/vehicle",
                            "session " + m.session + " has " + std::to_string(s.drivers.size()) + " vehicles, got " +
                                std::to_string(v)),
           -1;
  if (v < 0) {
    auto free = std::find(s.drivers.begin(), s.drivers.end(), nullptr);
    if (free == s.drivers.end())
      return c_.browsers.refuse(p, "join", "/role",
                              "every vehicle of session " + m.session + " has a driver (spectate instead)"),
             -1;
    v = static_cast<int>(free - s.drivers.begin());
  } else if (s.drivers[v] && s.drivers[v] != p) {
    return c_.browsers.refuse(p, "join", "/vehicle", "vehicle " + std::to_string(v) + " already has a driver"), -1;
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
  const std::string* doc = ps.role == Role::Drive ? c_.sessions.scenario(session) : nullptr;
  msg += ",\"scenario\":" + (doc && !doc->empty() ? quoted(*doc) : std::string("null")) +
         ",\"scale\":{\"drive_torque\":" + std::to_string(c_.cfg.scale.drive_torque) +
         ",\"brake_torque\":" + std::to_string(c_.cfg.scale.brake_torque) +
         ",\"steer\":" + std::to_string(c_.cfg.scale.steer) + "}}";
  return msg;
}

}  // namespace groundsim::web
