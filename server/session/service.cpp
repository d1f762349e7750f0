#include "service.hpp"

#include <cmath>
#include <thread>

#include "scenario/scenario.hpp"
#include "token.hpp"

namespace groundsim::session {
namespace {

int workerCount(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 2;
}

std::string joinIssues(const scenario::ScenarioError& e) {
  std::string out;
  for (const auto& issue : e.issues()) {
    if (!out.empty()) out += "; ";
    out += issue.str();
  }
  return out.empty() ? std::string(e.what()) : out;
}

}  // namespace

SessionService::SessionService(ServiceConfig cfg, Output& out)
    : cfg_(cfg), out_(out), pool_(workerCount(cfg.workers)) {
  cfg_.workers = pool_.workers();
}

SessionService::~SessionService() { shutdown("server stopping"); }

// ---- answers ----------------------------------------------------------------

void SessionService::fail(const Request& r, ErrorCode code, const std::string& error) {
  Event e;
  e.session_id = r.session_id;
  e.client_id = r.client_id;
  e.request_id = r.request_id;
  e.code = code;
  e.reason = error;
  out_.publishEvent(e);
  Reply reply;
  reply.op = r.op;
  reply.request_id = r.request_id;
  reply.client_id = r.client_id;
  reply.session_id = r.session_id;
  reply.ok = false;
  reply.code = code;
  reply.error = error;
  out_.publishReply(reply);
}

void SessionService::replyOk(const Request& r, Reply reply) {
  reply.op = r.op;
  reply.request_id = r.request_id;
  reply.client_id = r.client_id;
  reply.ok = true;
  out_.publishReply(reply);
}

void SessionService::reportBadInput(ErrorCode code, const std::string& channel, const std::string& reason) {
  Event e;
  e.code = code;
  e.channel = channel;
  e.reason = reason;
  out_.publishEvent(e);
}

// ---- lookup -----------------------------------------------------------------

std::shared_ptr<Session> SessionService::find(const std::string& id) {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = sessions_.find(id);
  return it == sessions_.end() ? nullptr : it->second;
}

std::shared_ptr<Session> SessionService::owned(const Request& r) {
  auto s = find(r.session_id);
  if (!s) {
    fail(r, ErrorCode::UnknownSession, "unknown session '" + r.session_id + "'");
    return nullptr;
  }
  if (!s->tokenMatches(r.token)) {
    fail(r, ErrorCode::Unauthorized,
         r.token.empty() ? "session " + r.session_id + " needs its token (from the create reply)"
                         : "wrong token for session " + r.session_id);
    return nullptr;
  }
  s->touch(Clock::now());
  return s;
}

bool SessionService::validSettings(const Request& r) {
  if (r.mode != 0 && !modeFromInt(r.mode)) {
    fail(r, ErrorCode::BadRequest, "unknown mode " + std::to_string(r.mode));
    return false;
  }
  if (!std::isfinite(r.rate) || r.rate < 0 || r.rate > cfg_.max_rate) {
    fail(r, ErrorCode::BadRequest,
         "rate must be in (0, " + std::to_string(cfg_.max_rate) + "], got " + std::to_string(r.rate));
    return false;
  }
  if (!std::isfinite(r.publish_rate) || r.publish_rate < 0 || r.publish_rate > cfg_.max_publish_rate) {
    fail(r, ErrorCode::BadRequest,
         "publish_rate must be in (0, " + std::to_string(cfg_.max_publish_rate) + "] Hz, got " +
             std::to_string(r.publish_rate));
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
      case Op::Stop: {
        auto s = owned(r);
        if (!s) return;
        {
          std::lock_guard<std::mutex> lk(mutex_);
          sessions_.erase(r.session_id);  // unknown from now on; the worker publishes its last frame
        }
        s->stop(ReplyTo{r.op, r.request_id, r.client_id}, "stopped by its owner");
        pool_.wake(s);
        return;
      }
      case Op::Scenario: {  // anyone may read a session's scenario, as its states
        auto s = find(r.session_id);
        if (!s) return fail(r, ErrorCode::UnknownSession, "unknown session '" + r.session_id + "'");
        Reply reply;
        reply.session_id = r.session_id;
        reply.scenario_json = s->scenarioJson();
        reply.scenario_name = s->name();
        reply.sessions.push_back(s->info(Clock::now()));
        return replyOk(r, std::move(reply));
      }
      case Op::Step:
        if (r.steps < 1 || r.steps > cfg_.max_steps_per_request)
          return fail(r, ErrorCode::BadRequest,
                      "steps must be in [1, " + std::to_string(cfg_.max_steps_per_request) + "], got " +
                          std::to_string(r.steps));
        [[fallthrough]];
      case Op::Reset:
      case Op::Pause:
      case Op::Resume:
      case Op::SetMode: {
        if (r.op == Op::SetMode && !validSettings(r)) return;
        auto s = owned(r);
        if (!s) return;
        s->post(r);
        pool_.wake(s);
        return;
      }
    }
    fail(r, ErrorCode::BadRequest, "unknown op " + std::to_string(static_cast<int>(r.op)));
  } catch (const std::exception& e) {
    fail(r, ErrorCode::Internal, std::string("internal error: ") + e.what());
  }
}

void SessionService::create(const Request& r) {
  if (r.scenario_json.size() > cfg_.max_scenario_bytes)
    return fail(r, ErrorCode::BadScenario,
                "scenario of " + std::to_string(r.scenario_json.size()) + " bytes exceeds the limit of " +
                    std::to_string(cfg_.max_scenario_bytes));
  if (!std::isfinite(r.duration))
    return fail(r, ErrorCode::BadRequest, "duration must be finite (< 0 runs until stopped)");
  if (!validSettings(r)) return;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    if (shut_down_) return fail(r, ErrorCode::Shutdown, "server is shutting down");
    const int used = static_cast<int>(sessions_.size()) + reserved_;
    if (used >= cfg_.max_sessions)
      return fail(r, ErrorCode::TooManySessions,
                  "too many sessions: " + std::to_string(used) + " of " + std::to_string(cfg_.max_sessions) +
                      " in use (stop one, or start the server with a larger --max-sessions)");
    ++reserved_;
  }
  // parsing and building may take a while for large grounds: not on the receive thread
  pool_.post([this, r] { build(r); });
}

void SessionService::build(const Request& r) {
  std::shared_ptr<Session> session;
  try {
    const scenario::Scenario sc = scenario::parseScenario(r.scenario_json);
    scenario::Scene scene = scenario::buildScene(sc);
    const int nveh = static_cast<int>(scene.built.model->vehicle_names.size());
    if (nveh < 1 || nveh > cfg_.max_vehicles)
      throw scenario::ScenarioError({{"/vehicles", "a session needs 1 to " + std::to_string(cfg_.max_vehicles) +
                                                       " vehicles, got " + std::to_string(nveh)}});
    SessionSetup setup;
    setup.token = newToken();
    setup.name = sc.name;
    setup.scenario_json = r.scenario_json;
    setup.vehicle_names = scene.vehicle_names.size() == static_cast<size_t>(nveh)
                              ? scene.vehicle_names
                              : scene.built.model->vehicle_names;
    setup.duration = r.duration == 0 ? scene.duration : r.duration;
    setup.mode = r.mode == 0 ? Mode::Realtime : *modeFromInt(r.mode);
    setup.rate = r.rate > 0 ? r.rate : 1.0;
    setup.publish_rate = r.publish_rate > 0 ? r.publish_rate : scene.output_rate;
    {
      std::lock_guard<std::mutex> lk(mutex_);
      do setup.id = newSessionId();
      while (sessions_.count(setup.id));
      session = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg_, out_, Clock::now());
      sessions_.emplace(setup.id, session);
      --reserved_;
    }
    Reply reply;
    reply.session_id = setup.id;
    reply.token = setup.token;
    reply.scenario_json = r.scenario_json;  // published for viewers and loggers (scenario_t)
    reply.scenario_name = sc.name;
    reply.sessions.push_back(session->info(Clock::now()));
    replyOk(r, std::move(reply));
    // settings near or beyond a stability limit run, but the creator hears of it
    for (const std::string& w : scene.warnings) {
      Event e;
      e.session_id = setup.id;
      e.client_id = r.client_id;
      e.request_id = r.request_id;
      e.severity = Severity::Warning;
      e.reason = w;
      out_.publishEvent(e);
    }
    pool_.wake(session);  // publishes the initial state, starts real time / fast stepping
    return;
  } catch (const scenario::ScenarioError& e) {
    fail(r, ErrorCode::BadScenario, "invalid scenario: " + joinIssues(e));
  } catch (const std::exception& e) {
    fail(r, ErrorCode::BadScenario, std::string("invalid scenario: ") + e.what());
  }
  std::lock_guard<std::mutex> lk(mutex_);
  if (!session) --reserved_;
}

// ---- controls ---------------------------------------------------------------

void SessionService::handleDrive(Drive d) {
  Request as_request;  // for the answers: drives have no request id
  as_request.client_id = d.client_id;
  as_request.session_id = d.session_id;
  as_request.token = d.token;
  auto refuse = [&](ErrorCode code, const std::string& why) {
    Event e;
    e.session_id = d.session_id;
    e.client_id = d.client_id;
    e.code = code;
    e.reason = why;
    out_.publishEvent(e);
  };
  try {
    auto s = find(d.session_id);
    if (!s) return refuse(ErrorCode::UnknownSession, "drive: unknown session '" + d.session_id + "'");
    if (!s->tokenMatches(d.token))
      return refuse(ErrorCode::Unauthorized, d.token.empty() ? "drive: session " + d.session_id + " needs its token"
                                                             : "drive: wrong token for session " + d.session_id);
    const auto& vehicles = s->vehicles();
    if (d.vehicle < 0 || d.vehicle >= static_cast<int>(vehicles.size()))
      return refuse(ErrorCode::BadControl, "drive: no vehicle " + std::to_string(d.vehicle) + " (session has " +
                                               std::to_string(vehicles.size()) + ")");
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
        return refuse(ErrorCode::BadControl, "drive: " + wheel + "drive torque " + std::to_string(c.drive_torque) +
                                                 " N m beyond the limit of " + std::to_string(cfg_.max_torque));
      if (c.brake_torque < 0 || c.brake_torque > cfg_.max_torque)
        return refuse(ErrorCode::BadControl, "drive: " + wheel + "brake torque " + std::to_string(c.brake_torque) +
                                                 " N m outside [0, " + std::to_string(cfg_.max_torque) + "]");
    }
    s->touch(d.received);
    s->post(std::move(d));
    pool_.wake(s);
  } catch (const std::exception& e) {
    refuse(ErrorCode::Internal, std::string("drive: internal error: ") + e.what());
  }
}

// ---- upkeep -----------------------------------------------------------------

void SessionService::housekeeping() {
  if (cfg_.idle_timeout <= 0) return;
  const TimePoint now = Clock::now();
  std::vector<std::shared_ptr<Session>> idle;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    for (auto it = sessions_.begin(); it != sessions_.end();) {
      if (it->second->idleSeconds(now) > cfg_.idle_timeout) {
        idle.push_back(it->second);
        it = sessions_.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (auto& s : idle) {
    s->stop(std::nullopt, "reclaimed after " + std::to_string(cfg_.idle_timeout) + " s without its owner");
    pool_.wake(s);
  }
}

ServiceStatus SessionService::status() {
  ServiceStatus st;
  st.workers = cfg_.workers;
  st.max_sessions = cfg_.max_sessions;
  st.load = pool_.takeLoad();
  const TimePoint now = Clock::now();
  std::lock_guard<std::mutex> lk(mutex_);
  st.sessions.reserve(sessions_.size());
  for (const auto& [id, s] : sessions_) st.sessions.push_back(s->info(now));
  return st;
}

void SessionService::shutdown(const std::string& reason) {
  std::map<std::string, std::shared_ptr<Session>> sessions;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    if (shut_down_) return;
    shut_down_ = true;
  }
  pool_.stop();  // no worker runs a session after this
  {
    std::lock_guard<std::mutex> lk(mutex_);
    sessions.swap(sessions_);
  }
  for (auto& [id, s] : sessions) {
    s->stop(std::nullopt, reason);
    s->run(Clock::now());  // publishes the final frame on this thread
  }
}

}  // namespace groundsim::session
