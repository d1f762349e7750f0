#include "scenario/object_reader.hpp"
#include "service.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <new>
#include <thread>

#include "accuracy/choice_cache.hpp"
#include "accuracy/live_estimate.hpp"
#include "accuracy/pilot.hpp"
#include "answers.hpp"
#include "scenario/scenario.hpp"
#include "service_detail.hpp"
#include "token.hpp"

namespace groundsim::session {
using service_detail::claimId;
using service_detail::joinIssues;
using service_detail::MissingAssetsError;

namespace {

int workerCount(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 2;
}

std::string sizeText(std::uint64_t n) {
  char buf[32];
  if (n >= 10'000'000) std::snprintf(buf, sizeof buf, "%.0f MB", n / 1e6);
  else if (n >= 10'000) std::snprintf(buf, sizeof buf, "%.0f kB", n / 1e3);
  else std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(n));
  return buf;
}

// "<field>: <value> is outside [lo, hi] <unit>", or "" when inside.
std::string outside(const char* field, double x, double lo, double hi, const char* unit) {
  if (std::isfinite(x) && x >= lo && x <= hi) return "";
  return std::string(field) + ": " + scenario::formatNumber(x) + " is outside [" + scenario::formatNumber(lo) + ", " + scenario::formatNumber(hi) + "]" + unit;
}

// What a create runs: its scenario document, and with a tolerance the live
// estimate and refinement policy of the settings the pilot chose.
struct Chosen {
  std::string scenario_json;
  std::shared_ptr<accuracy::LiveEstimate> live;
  accuracy::RefinementPolicy refinement;
};

// A tolerance: the pilot chooses the settings here, on the worker (it runs
// the scene a few times: seconds for a large one), and sc becomes the
// chosen scenario; the session keeps the chosen document without its
// `accuracy`, so a re-simulation runs the same settings without a pilot
// whose timing may choose others. Without one: the request's document.
Chosen applyTolerance(scenario::Scenario& sc, const Request& r, const scenario::FileAccess& files,
                      const scenario::Budget& budget) {
  Chosen out;
  out.scenario_json = r.scenario_json;
  if (!sc.accuracy) return out;
  const scenario::AccuracySpec spec = *sc.accuracy;
  const accuracy::Choice choice =
      accuracy::ChoiceCache::shared().choose(sc, spec.tolerance, accuracy::pilotOptions(spec, budget));
  std::fprintf(stderr, "groundsim-server: %s: %s%s\n", sc.name.c_str(), choice.line().c_str(),
               choice.from_cache ? " (chosen before for the same content: no pilot)" : "");
  nlohmann::json chosen = choice.scenario.document;
  chosen.erase("accuracy");
  out.scenario_json = chosen.dump();
  sc = scenario::parseScenario(std::move(chosen), budget, files);
  if (spec.live_estimate) {
    accuracy::LiveEstimateOptions lo;
    const double run = r.duration == 0 ? sc.duration : r.duration;
    lo.duration = run > 0 ? run : 0.0;  // a session without end: windows of 0.25 s
    out.live = std::make_shared<accuracy::LiveEstimate>(sc, choice.order, lo);
    out.live->expect(choice.prediction(), sc.duration);
    out.refinement = accuracy::refinementPolicy(spec);
  }
  return out;
}

void checkVehicleCount(const scenario::Scene& scene, int max_vehicles) {
  const int nveh = static_cast<int>(scene.built.model->vehicle_names.size());
  if (nveh < 1 || nveh > max_vehicles)
    throw scenario::ScenarioError({{"/vehicles", "a session needs 1 to " + std::to_string(max_vehicles) +
                                                     " vehicles, got " + std::to_string(nveh)}});
}

// The new session's setup from the request and its built scene (a fresh
// token; the id is claimed after).
SessionSetup setupFor(const Request& r, const scenario::Scenario& sc, const scenario::Scene& scene, Chosen& chosen,
                      std::shared_ptr<const scenario::AssetBytes> assets) {
  const int nveh = static_cast<int>(scene.built.model->vehicle_names.size());
  SessionSetup setup;
  setup.token = newToken();
  setup.name = sc.name;
  setup.scenario_json = chosen.scenario_json;
  if (sc.race) setup.bot_policy = sc.race->bot_policy_text;
  setup.live_estimate = std::move(chosen.live);
  setup.refinement = chosen.refinement;
  setup.vehicle_names = scene.vehicle_names.size() == static_cast<size_t>(nveh)
                            ? scene.vehicle_names
                            : scene.built.model->vehicle_names;
  setup.duration = r.duration == 0 ? scene.duration : r.duration;
  setup.mode = r.mode == 0 ? Mode::Realtime : *modeFromInt(r.mode);
  setup.rate = r.rate > 0 ? r.rate : 1.0;
  setup.publish_rate = r.publish_rate > 0 ? r.publish_rate : scene.output_rate;
  setup.control_tables = scene.control_tables;
  setup.assets = std::move(assets);
  return setup;
}

}  // namespace

namespace service_detail {

std::string joinIssues(const scenario::ScenarioError& e) {
  const std::string out = e.lines("; ");
  return out.empty() ? std::string(e.what()) : out;
}

std::int64_t claimId(Registry& registry, Ownership* ownership, const std::string& placement, std::string& id) {
  for (int attempt = 0;; ++attempt) {
    id = registry.newId();
    if (!ownership) return 0;
    if (const std::int64_t epoch = ownership->claim(id, placement); epoch > 0) return epoch;
    registry.cancelId(id);
    if (attempt == 7) throw std::runtime_error("the fleet refused 8 fresh session ids in a row");
  }
}

}  // namespace service_detail

SessionService::SessionService(ServiceConfig cfg, Output& out, const SessionClock& clock)
    : cfg_(cfg), out_(out), clock_(clock), create_rate_(cfg.client_creates_per_minute), assets_(cfg.assets), pool_(workerCount(cfg.workers), cfg.max_build_jobs) {
  cfg_.workers = pool_.workers();
  cfg_.budget.max_vehicles = std::min(cfg_.budget.max_vehicles, cfg_.max_vehicles);
  cfg_.budget.max_document_bytes = std::min(cfg_.budget.max_document_bytes, cfg_.max_scenario_bytes);
}

SessionService::~SessionService() { shutdown("server stopping"); }

// ---- answers ----------------------------------------------------------------

void SessionService::fail(const Request& r, ErrorCode code, const std::string& error) noexcept {
  try {
    refuse(out_, makeReply(replyTo(r), r.session_id, false, code, error));
  } catch (...) {
    // the transport reports its own failures; nothing leaves the service
  }
}

void SessionService::replyOk(const Request& r, Reply reply) {
  const std::string id = reply.session_id;
  Reply base = makeReply(replyTo(r), id, true);
  base.token = std::move(reply.token);
  base.t = reply.t;
  base.sessions = std::move(reply.sessions);
  base.state = std::move(reply.state);
  base.scenario_json = std::move(reply.scenario_json);  // published as scenario_t (create, Op::Scenario)
  base.scenario_name = std::move(reply.scenario_name);
  out_.publishReply(base);
}

void SessionService::reportBadInput(ErrorCode code, const std::string& channel, const std::string& reason) {
  Event e = sessionEvent("", Severity::Error, code, reason);
  e.channel = channel;
  out_.publishEvent(e);
}

// ---- assets -----------------------------------------------------------------

void SessionService::handleAssetPart(const AssetPart& p, const std::string& channel) {
  const std::string why = assets_.addPart(p, clock_.now());
  if (why.empty()) return;
  Event e = sessionEvent("", Severity::Error, ErrorCode::BadRequest, why);
  e.client_id = p.client_id;
  e.channel = channel;
  out_.publishEvent(e);
}

scenario::FileAccess SessionService::filesFor(const nlohmann::json& doc, std::int64_t request_id,
                                              const std::string& client_id,
                                              std::shared_ptr<const scenario::AssetBytes>* held) {
  const std::vector<scenario::AssetRef> refs = scenario::assetManifest(doc);
  std::string why;
  const std::vector<MissingAsset> missing = assets_.missing(refs, &why);
  if (!why.empty()) {
    const auto colon = why.find(": ");
    throw scenario::ScenarioError({{why.substr(0, colon), why.substr(colon + 2)}});
  }
  if (!missing.empty()) {
    std::string list;
    for (const MissingAsset& m : missing) {
      out_.publishAssetWant(AssetWant{request_id, client_id, m});
      list += (list.empty() ? "" : ", ") + std::string("\"") + m.ref.name + "\" (sha256 " + m.ref.sha256.substr(0, 12) +
              "..., " + sizeText(m.ref.size) + ", " + std::to_string(m.parts.size()) + " of " +
              std::to_string(m.nparts) + " parts)";
    }
    throw MissingAssetsError("this server does not hold the scenario's files yet: " + list +
                             "; a client sends them on GROUNDSIM_ASSET and creates again (docs/protocol.md, Assets)");
  }
  auto bytes = std::make_shared<scenario::AssetBytes>();
  for (const auto& r : refs) {
    auto b = assets_.find(r.sha256);
    // evicted between the two looks: only assets no session holds are, and this create is asking again
    if (!b) throw MissingAssetsError("\"" + r.name + "\" left the server's asset store while the create was built; create again");
    (*bytes)[r.name] = std::move(b);
  }
  *held = bytes;
  return scenario::FileAccess::fromAssets(std::move(bytes), cfg_.terrain_dir);
}

// ---- lookup -----------------------------------------------------------------

std::shared_ptr<HostedSession> SessionService::owned(const Request& r) {
  auto s = registry_.find(r.session_id);
  if (const OwnerCheck c = checkOwner(s.get(), r.session_id, r.token); !c) {
    fail(r, c.code, c.why);
    return nullptr;
  }
  s->touch(clock_.now());
  return s;
}

// One stop for every kind: unknown from now on (listed among the ended);
// the session answers, publishes its last state and takes no more work.
void SessionService::stop(const Request& r) {
  auto s = owned(r);
  if (!s) return;
  if (!registry_.retire(r.session_id, clock_.now()))  // stopped or reclaimed since the lookup
    return fail(r, ErrorCode::UnknownSession, "unknown session '" + r.session_id + "'");
  if (ownership_) ownership_->release(r.session_id);
  s->stop(ReplyTo{r.op, r.request_id, r.client_id}, "stopped by its owner");
  pool_.wake(s);
}

bool SessionService::validSettings(const Request& r) {
  if (r.mode != 0 && !modeFromInt(r.mode)) {
    fail(r, ErrorCode::BadRequest, "mode: unknown mode " + std::to_string(r.mode) + " (1 realtime, 2 fast, 3 lockstep)");
    return false;
  }
  // 0 means "unchanged" or "the default"; anything else must be in range
  std::string why;
  if (r.rate != 0) why = outside("rate", r.rate, cfg_.min_rate, cfg_.max_rate, " (real-time factor)");
  if (why.empty() && r.publish_rate != 0)
    why = outside("publish_rate", r.publish_rate, cfg_.min_publish_rate, cfg_.max_publish_rate,
                  " Hz (states per simulated second)");
  if (!why.empty()) {
    fail(r, ErrorCode::BadRequest, why);
    return false;
  }
  return true;
}

// ---- requests ---------------------------------------------------------------

void SessionService::handleRequest(const Request& r) {
  try {
    switch (r.op) {
      case Op::Create:
        return create(r);
      case Op::List: {
        Reply reply;
        reply.sessions = status().sessions;
        return replyOk(r, std::move(reply));
      }
      case Op::Stop:
        return stop(r);
      case Op::Drain:  // the transport's (it knows the server's id and the fleet)
        return fail(r, ErrorCode::BadRequest, "op: drain is not handled by this server");
      case Op::Scenario: {  // anyone may read a session's scenario, as its states
        auto s = registry_.find(r.session_id);
        if (!s) return fail(r, ErrorCode::UnknownSession, "unknown session '" + r.session_id + "'");
        Reply reply;
        reply.session_id = r.session_id;
        reply.scenario_json = s->scenarioJson();
        reply.scenario_name = s->name();
        reply.sessions.push_back(s->info(clock_.now()));
        return replyOk(r, std::move(reply));
      }
      case Op::Step:
        if (r.steps < 1 || r.steps > cfg_.max_steps_per_request)
          return fail(r, ErrorCode::BadRequest,
                      "steps: " + std::to_string(r.steps) + " is outside [1, " +
                          std::to_string(cfg_.max_steps_per_request) + "]");
        [[fallthrough]];
      case Op::Reset:
      case Op::Pause:
      case Op::Resume:
      case Op::SetMode: {
        if (r.op == Op::SetMode && !validSettings(r)) return;
        auto found = registry_.find(r.session_id);
        if (found && found->kind() == HostedSession::Kind::Vectorised)
          return fail(r, ErrorCode::WrongMode, "session " + r.session_id +
                                                   " is vectorised: reset and step it with vec_request_t on "
                                                   "GROUNDSIM_VEC_REQUEST, stop it with OP_STOP");
        auto s = std::dynamic_pointer_cast<Session>(owned(r));
        if (!s) return;
        s->post(r);
        pool_.wake(s);
        return;
      }
    }
    fail(r, ErrorCode::BadRequest, "unknown op " + std::to_string(static_cast<int>(r.op)));
  } catch (const std::exception& e) {
    fail(r, ErrorCode::Internal, std::string("internal error: ") + e.what());
  } catch (...) {
    fail(r, ErrorCode::Internal, "internal error: unknown exception");
  }
}

// The server's capacity, then the client's own bounds (--client-sessions,
// --client-creates): one client creating in a loop cannot take every slot.
OwnerCheck SessionService::admitCreate(const std::string& client_id) {
  const std::string client = clientKey(client_id);
  if (OwnerCheck rate = create_rate_.take(client, clock_.now()); !rate) return rate;
  return registry_.admit(cfg_.max_sessions, &client, cfg_.max_client_sessions);
}

void SessionService::create(const Request& r) {
  if (r.scenario_json.size() > cfg_.max_scenario_bytes)
    return fail(r, ErrorCode::BadScenario,
                "scenario_json: " + std::to_string(r.scenario_json.size()) + " bytes, at most " +
                    std::to_string(cfg_.max_scenario_bytes) + " (server --max-scenario-bytes)");
  if (!std::isfinite(r.duration))
    return fail(r, ErrorCode::BadRequest, "duration: must be finite (< 0 runs until stopped), got " + scenario::formatNumber(r.duration));
  if (!validSettings(r)) return;
  if (const OwnerCheck a = admitCreate(r.client_id); !a) return fail(r, a.code, a.why);
  // parsing and building may take a while for large grounds: not on the receive thread
  pool_.post([this, r] { build(r); });  // build() answers, whatever happens
}

void SessionService::build(const Request& r) {
  std::shared_ptr<Session> session;
  std::string id;        // given by the registry, until the session takes it
  bool claimed = false;  // in the fleet: released again if the session is not built
  try {
    // the budget is checked in validation, before anything is built
    nlohmann::json doc = scenario::parseScenarioDocument(r.scenario_json, cfg_.budget);
    std::shared_ptr<const scenario::AssetBytes> assets;
    const scenario::FileAccess files = filesFor(doc, r.request_id, r.client_id, &assets);
    scenario::Scenario sc = scenario::parseScenario(std::move(doc), cfg_.budget, files);
    Chosen chosen = applyTolerance(sc, r, files, cfg_.budget);
    if (r.duration > 0) scenario::checkRunLength(sc, r.duration, cfg_.budget);  // the request's own duration
    scenario::Scene scene = scenario::buildScene(sc);
    checkVehicleCount(scene, cfg_.max_vehicles);
    SessionSetup setup = setupFor(r, sc, scene, chosen, std::move(assets));
    const std::int64_t epoch = claimId(registry_, ownership_, r.client_id + "/" + std::to_string(r.request_id), id);
    claimed = epoch > 0;
    setup.id = id;
    session = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg_, out_, clock_.now(),
                                        clock_);
    session->setEpoch(epoch);
    session->setCreator(clientKey(r.client_id));
    registry_.insert(session);
    if (cfg_.replica_interval > 0) out_.publishReplica(session->scenarioReplica());
    Reply reply;
    reply.session_id = setup.id;
    reply.token = setup.token;
    reply.scenario_json = chosen.scenario_json;  // published for viewers and loggers (scenario_t): what runs
    reply.scenario_name = sc.name;
    reply.sessions.push_back(session->info(clock_.now()));
    replyOk(r, std::move(reply));
    // settings near or beyond a stability limit run, but the creator hears of it
    for (const std::string& w : scene.warnings) {
      Event e = refusalEvent(replyTo(r), setup.id, ErrorCode::None, w);
      e.severity = Severity::Warning;
      out_.publishEvent(e);
    }
    pool_.wake(session);  // publishes the initial state, starts real time / fast stepping
    return;
  } catch (const scenario::ScenarioError& e) {
    fail(r, ErrorCode::BadScenario, "invalid scenario: " + joinIssues(e));
  } catch (const MissingAssetsError& e) {
    fail(r, ErrorCode::MissingAssets, e.what());
  } catch (const UnavailableError& e) {
    fail(r, ErrorCode::Unavailable, std::string("unavailable: ") + e.what() + "; create again");
  } catch (const std::bad_alloc&) {
    fail(r, ErrorCode::BadScenario, "invalid scenario: building it needs more memory than the server has");
  } catch (const std::exception& e) {
    fail(r, session ? ErrorCode::Internal : ErrorCode::BadScenario,
         std::string(session ? "internal error: " : "invalid scenario: ") + e.what());
  } catch (...) {
    fail(r, ErrorCode::Internal, "internal error: unknown exception while building the scenario");
  }
  if (session) return;
  const std::string client = clientKey(r.client_id);
  registry_.cancel(id, &client);
  if (claimed) ownership_->release(id);
}

// ---- controls ---------------------------------------------------------------

void SessionService::handleDrive(Drive d) {
  Request as_request;  // for the answers: drives have no request id
  as_request.client_id = d.client_id;
  as_request.session_id = d.session_id;
  as_request.token = d.token;
  auto refuse = [&](ErrorCode code, const std::string& why) {
    Event e = sessionEvent(d.session_id, Severity::Error, code, why);
    e.client_id = d.client_id;
    out_.publishEvent(e);
  };
  try {
    auto found = registry_.find(d.session_id);
    if (const OwnerCheck c = checkOwner(found.get(), d.session_id, d.token); !c) return refuse(c.code, "drive: " + c.why);
    auto s = std::dynamic_pointer_cast<Session>(found);
    if (!s)
      return refuse(ErrorCode::WrongMode, "drive: session " + d.session_id +
                                              " is vectorised: its actions go in vec_request_t OP_STEP");
    const auto& vehicles = s->vehicles();
    if (d.vehicle < 0 || d.vehicle >= static_cast<int>(vehicles.size()))
      return refuse(ErrorCode::BadControl, "drive: no vehicle " + std::to_string(d.vehicle) + " (session has " +
                                               std::to_string(vehicles.size()) + ")");
    if (vehicles[d.vehicle].road_car >= 0)
      return refuse(ErrorCode::BadControl, "drive: vehicle " + std::to_string(d.vehicle) +
                                               " is a road car (kind \"road_car\"): drive it with controls_t");
    const size_t n = vehicles[d.vehicle].wheels.size();
    if (d.wheels.size() != n)
      return refuse(ErrorCode::BadControl, "drive: vehicle " + std::to_string(d.vehicle) + " has " +
                                               std::to_string(n) + " wheels, command has " +
                                               std::to_string(d.wheels.size()));
    for (size_t k = 0; k < n; ++k) {
      const WheelControl& c = d.wheels[k];
      const std::string wheel = "wheel " + std::to_string(k) + ": ";
      if (!std::isfinite(c.drive_torque) || !std::isfinite(c.brake_torque) || !std::isfinite(c.steer))
        return refuse(ErrorCode::BadControl, "drive: " + wheel + "non-finite value (NaN or infinity)");
      if (std::abs(c.drive_torque) > cfg_.max_torque)
        return refuse(ErrorCode::BadControl, "drive: " + wheel + "drive torque " + scenario::formatNumber(c.drive_torque) +
                                                 " N m beyond the limit of " + scenario::formatNumber(cfg_.max_torque));
      if (c.brake_torque < 0 || c.brake_torque > cfg_.max_torque)
        return refuse(ErrorCode::BadControl, "drive: " + wheel + "brake torque " + scenario::formatNumber(c.brake_torque) +
                                                 " N m outside [0, " + scenario::formatNumber(cfg_.max_torque) + "]");
    }
    s->touch(d.received);
    s->post(std::move(d));
    pool_.wake(s);
  } catch (const std::exception& e) {
    try {
      refuse(ErrorCode::Internal, std::string("drive: internal error: ") + e.what());
    } catch (...) {
    }
  } catch (...) {
  }
}

void SessionService::handleControls(CarDrive d) {
  auto refuse = [&](ErrorCode code, const std::string& why) {
    Event e = sessionEvent(d.session_id, Severity::Error, code, "controls: " + why);
    e.client_id = d.client_id;
    out_.publishEvent(e);
  };
  try {
    auto found = registry_.find(d.session_id);
    if (const OwnerCheck c = checkOwner(found.get(), d.session_id, d.token); !c) return refuse(c.code, c.why);
    auto s = std::dynamic_pointer_cast<Session>(found);
    if (!s)
      return refuse(ErrorCode::WrongMode,
                    "session " + d.session_id + " is vectorised: its actions go in vec_request_t OP_STEP");
    const auto& vehicles = s->vehicles();
    if (d.vehicle < 0 || d.vehicle >= static_cast<int>(vehicles.size()))
      return refuse(ErrorCode::BadControl, "vehicle: no vehicle " + std::to_string(d.vehicle) + " (session has " +
                                               std::to_string(vehicles.size()) + ")");
    const VehicleWheels& vw = vehicles[d.vehicle];
    if (vw.road_car < 0)
      return refuse(ErrorCode::BadControl, "vehicle: vehicle " + std::to_string(d.vehicle) +
                                               " is not a road car (kind \"road_car\"); drive it with drive_t");
    const CarControls& c = d.controls;
    const struct { const char* field; double v, lo, hi; } ranges[] = {
        {"throttle", c.throttle, 0.0, 1.0}, {"brake", c.brake, 0.0, 1.0}, {"steer", c.steer, -1.0, 1.0}};
    for (const auto& r : ranges) {
      if (!std::isfinite(r.v))
        return refuse(ErrorCode::BadControl, std::string(r.field) + ": " + scenario::formatNumber(r.v) + " is not finite");
      if (r.v < r.lo || r.v > r.hi)
        return refuse(ErrorCode::BadControl, std::string(r.field) + ": " + scenario::formatNumber(r.v) + " outside [" + scenario::formatNumber(r.lo) +
                                                 ", " + scenario::formatNumber(r.hi) + "]");
    }
    if (c.gear < CarControls::kNeutral || c.gear > vw.gears)
      return refuse(ErrorCode::BadControl, "gear: " + std::to_string(c.gear) + " is not 0 (auto), -1 (reverse), "
                                           "-2 (neutral) or a gear 1.." + std::to_string(vw.gears));
    s->touch(d.received);
    s->post(std::move(d));
    pool_.wake(s);
  } catch (const std::exception& e) {
    try {
      refuse(ErrorCode::Internal, std::string("internal error: ") + e.what());
    } catch (...) {
    }
  } catch (...) {
  }
}

// ---- upkeep -----------------------------------------------------------------

void SessionService::housekeeping() {
  const TimePoint now = clock_.now();
  assets_.expire(now);
  for (auto& s : registry_.reclaim(now, cfg_.idle_timeout, cfg_.ended_linger)) {
    if (ownership_) ownership_->release(s->id());
    s->stop(std::nullopt, "reclaimed after " + scenario::formatNumber(cfg_.idle_timeout) + " s without its owner");
    pool_.wake(s);
  }
}

ServiceStatus SessionService::status() {
  ServiceStatus st;
  st.workers = cfg_.workers;
  st.max_sessions = cfg_.max_sessions;
  st.load = pool_.takeLoad();
  Registry::Listing l = registry_.list(clock_.now());
  st.sessions = std::move(l.live);
  st.ended = std::move(l.ended);
  return st;
}

void SessionService::shutdown(const std::string& reason) {
  if (!registry_.close()) return;  // no admission from now on
  pool_.stop();                    // no worker runs a session (or builds one) after this
  for (auto& s : registry_.takeAll()) {
    s->stop(std::nullopt, reason);
    // on this thread: a simulation publishes its final frame in one run; a
    // batch answers what was queued, one request per run, then stops
    if (s->kind() == HostedSession::Kind::Vectorised)
      while (s->run(clock_.now())) {
      }
    else
      s->run(clock_.now());
  }
}

}  // namespace groundsim::session
