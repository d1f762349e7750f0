#include "bridge/creates.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>

#include "bridge/hub.hpp"
#include "protocol/assets_client.hpp"
#include "protocol/names.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::web {

namespace asio = boost::asio;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// a browser's mode by its name (protocol/names.hpp); real time when it names none
std::int8_t modeValue(const std::string& m) {
  const int v = net::modeFromName(m);
  return static_cast<std::int8_t>(v != 0 ? v : groundsim::request_t::MODE_REALTIME);
}

std::string carRange(const ShippedScenario& s) {
  return std::to_string(s.min_cars) + (s.max_cars > s.min_cars ? "-" + std::to_string(s.max_cars) : std::string());
}

}  // namespace

Creates::Creates(const HubContext& c, const std::map<std::string, ShippedScenario>& scenarios, Join join)
    : c_(c), scenarios_(scenarios), join_(std::move(join)) {}

void Creates::create(Peer* p, PeerState& ps, const CreateMsg& m) {
  if (!m.player.empty()) ps.player = m.player;
  auto sc = scenarios_.find(m.config);
  if (sc == scenarios_.end())
    return c_.browsers.refuse(p, "create", "/config", "no shipped scenario named \"" + m.config + "\"");
  if (!fits(p, m, sc->second) || !allowed(p, ps, m, sc->second)) return;
  std::optional<std::string> doc = document(p, m);
  if (!doc) return;
  // the files it names go with it, read next to it (docs/protocol.md, Assets)
  const std::filesystem::path file = std::filesystem::path(c_.cfg.configs_dir) / m.config;
  net::ScenarioWithAssets sent;
  try {
    sent = net::withAssets(*doc, file.parent_path().string());
  } catch (const scenario::ScenarioError& e) {
    return c_.browsers.refuse(p, "create", "/config", m.config + ": " + e.lines("; "));
  }
  for (const scenario::Asset& a : sent.assets) asset_bytes_[a.ref.sha256] = a.bytes;
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_CREATE;
  r.scenario_json = std::move(sent.json);
  r.mode = modeValue(m.mode);
  r.publish_rate = publishRateFor(c_.cfg.limits, m.publish_rate, sc->second.output_rate);
  r.duration = -1;  // a game runs until its players leave
  // the server counts each browser's sessions and creates on its own (--client-sessions, --client-creates)
  r.client_id = c_.requests.browserClientId(ps.serial);  // a principal of its own (protocol/client_id.hpp)
  ++ps.creating;
  round(p, ps.serial, std::move(r), std::make_shared<const std::vector<scenario::Asset>>(std::move(sent.assets)),
        m.drive, 0);
}

bool Creates::fits(Peer* p, const CreateMsg& c, const ShippedScenario& s) {
  if (c.vehicles > 0 && (c.vehicles < s.min_cars || c.vehicles > s.max_cars)) {
    c_.browsers.refuse(p, "create", "/vehicles",
                     c.config + " hosts " + carRange(s) + " cars (" + s.limit + "), got " + std::to_string(c.vehicles));
    return false;
  }
  if ((c.bots >= 0 || c.bot_skill > 0.0) && !s.race) {
    c_.browsers.refuse(p, "create", "/bots", c.config + " is not a race: bots drive in races");
    return false;
  }
  const int players = c.vehicles > 0 ? c.vehicles : s.vehicles - s.bots;
  if (c.bots > 0 && s.grid > 0 && players + c.bots > s.grid) {
    c_.browsers.refuse(p, "create", "/bots",
                     c.config + "'s grid has " + std::to_string(s.grid) + " slots: " + std::to_string(players) +
                         " players leave room for " + std::to_string(std::max(0, s.grid - players)) +
                         " bots, got " + std::to_string(c.bots));
    return false;
  }
  return true;
}

bool Creates::allowed(Peer* p, PeerState& ps, const CreateMsg& c, const ShippedScenario& s) {
  if (c_.cfg.limits.sessions > 0 && c_.sessions.ownedBy(ps.serial) + ps.creating >= c_.cfg.limits.sessions) {
    // what it left behind would end within --orphan-stop anyway
    for (auto& [id, e] : c_.sessions)
      if (e.creator == ps.serial && e.owned() && e.watchers.empty()) stop(id, e);
  }
  const int cars = c.vehicles > 0 ? c.vehicles : s.vehicles;
  const std::optional<Refusal> no = ps.allowance->create(c_.cfg.limits, c.mode, cars, c.publish_rate,
                                                         c_.sessions.ownedBy(ps.serial) + ps.creating, Clock::now());
  if (no) c_.browsers.refuse(p, "create", no->field, no->reason);
  return !no;
}

std::optional<std::string> Creates::document(Peer* p, const CreateMsg& m) {
  std::ifstream f(std::filesystem::path(c_.cfg.configs_dir) / m.config);
  std::stringstream text;
  text << f.rdbuf();
  std::string doc = text.str();
  if (m.bots >= 0 || m.bot_skill > 0.0) {
    try {
      doc = withBots(doc, m.bots, m.bot_skill);
    } catch (const scenario::ScenarioError& e) {
      c_.browsers.refuse(p, "create", "/bots", e.lines("; "));
      return std::nullopt;
    }
  }
  if (m.vehicles > 0) {
    try {
      doc = withVehicles(doc, m.vehicles, c_.cfg.vehicle_margin);
    } catch (const std::exception& e) {
      c_.browsers.refuse(p, "create", "/vehicles", std::string("cannot copy this scenario's vehicle: ") + e.what());
      return std::nullopt;
    }
  }
  return doc;
}

void Creates::round(Peer* p, std::uint64_t serial, groundsim::request_t r,
                    std::shared_ptr<const std::vector<scenario::Asset>> assets, bool drive, int round) {
  const std::string doc = r.scenario_json;
  c_.requests.send(r, [this, p, serial, drive, doc, r, assets, round](const groundsim::reply_t* rep) {
    // the browser may have gone (and another taken its address): known by its serial
    PeerState* ps = c_.browsers.find(p, serial);
    const bool again = rep && !rep->ok && rep->error_code == groundsim::asset_want_t::ERR_MISSING_ASSETS &&
                       !assets->empty() && round + 1 < net::kAssetRounds && ps;
    if (ps && !again) --ps->creating;
    if (rep && rep->ok) return created(ps ? p : nullptr, serial, *rep, doc, drive);
    if (!ps) return;
    if (!rep) return c_.browsers.refuse(p, "create", "", "no server answered (is groundsim-server running on this LCM URL?)");
    if (again) return sendAssetsAndRetry(p, serial, r, assets, drive, round, rep->request_id);
    c_.browsers.refuse(p, "create", "", rep->error);
  });
}

void Creates::sendAssetsAndRetry(Peer* p, std::uint64_t serial, groundsim::request_t r,
                                 std::shared_ptr<const std::vector<scenario::Asset>> assets, bool drive, int round,
                                 std::int64_t answered) {
  std::vector<groundsim::asset_want_t> wants;
  if (auto w = wants_.find(answered); w != wants_.end()) {
    wants = std::move(w->second);
    wants_.erase(w);
  }
  // a large file takes a while to send: not on the I/O thread
  c_.worker.post([this, p, serial, r, assets, drive, round, wants] {
    std::string error;
    try {
      if (c_.bus.assets) c_.bus.assets(*assets, wants);
    } catch (const std::exception& e) {
      error = std::string("sending the scenario's files: ") + e.what();
    }
    asio::post(c_.io, [this, p, serial, r, assets, drive, round, error] {
      PeerState* ps = c_.browsers.find(p, serial);
      if (!ps) return;
      if (!error.empty()) {
        --ps->creating;
        return c_.browsers.refuse(p, "create", "", error);
      }
      this->round(p, serial, r, assets, drive, round + 1);
    });
  });
}

void Creates::created(Peer* p, std::uint64_t serial, const groundsim::reply_t& rep, const std::string& doc,
                      bool drive) {
  SessionEntry& s = c_.sessions.open(rep.session_id);
  s.token = rep.token;  // kept here: never sent to a browser
  s.creator = serial;
  s.unwatched_since = Clock::now();  // until someone watches: a create nobody joins ends too
  c_.sessions.setScenario(rep.session_id, doc);
  if (!p) return;  // its browser left before the reply: ended by stopOrphans as nobody watches it
  Browsers::send(p, json{{"op", "created"}, {"session", rep.session_id}}.dump());
  JoinMsg j;
  j.session = rep.session_id;
  j.role = drive ? Role::Drive : Role::Spectate;
  join_(p, j);
}

void Creates::noteWant(const groundsim::asset_want_t& w) {
  if (wants_.size() > 64) wants_.erase(wants_.begin());  // creates long answered
  auto& list = wants_[w.request_id];
  if (list.size() < scenario::kMaxAssets) list.push_back(w);  // a create names at most kMaxAssets files
}

scenario::FileAccess Creates::knownAssets(const std::string& scenario_json) const {
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

void Creates::stop(const std::string& id, SessionEntry& s) {
  c_.requests.send(Requests::stop(id, s.token), nullptr);
  s.token.clear();
  s.unwatched_since = {};
}

void Creates::stopOrphans(Clock::time_point now) {
  const auto after = std::chrono::milliseconds(static_cast<int>(c_.cfg.orphan_stop_s * 1000));
  for (auto& [id, s] : c_.sessions) {
    if (!s.owned() || !s.watchers.empty() || s.unwatched_since == Clock::time_point{}) continue;
    if (now - s.unwatched_since >= after) stop(id, s);
  }
}

void Creates::stopAll() {
  for (auto& [id, s] : c_.sessions) {
    if (!s.owned()) continue;
    c_.requests.sendUnanswered(Requests::stop(id, s.token));
    s.token.clear();
  }
}

}  // namespace groundsim::web
