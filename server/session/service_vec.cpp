// SessionService: vectorised sessions (VecRequest): their create, build and
// requests.
#include "service.hpp"

#include <new>
#include <string>

#include "answers.hpp"
#include "experiments/vec_env.hpp"
#include "scenario/scenario.hpp"
#include "service_detail.hpp"
#include "token.hpp"

namespace groundsim::session {
using service_detail::claimId;
using service_detail::joinIssues;
using service_detail::MissingAssetsError;

// ---- vectorised sessions ----------------------------------------------------

void SessionService::failVec(const VecRequest& r, ErrorCode code, const std::string& field,
                             const std::string& error) noexcept {
  try {
    const VecReply reply = refusedVecReply(r, r.session_id, code, field, field.empty() ? error : field + ": " + error);
    out_.publishEvent(refusalEvent(ReplyTo{Op::List, r.request_id, r.client_id}, r.session_id, code, reply.error));
    out_.publishVecReply(reply);
  } catch (...) {
  }
}

void SessionService::handleVecRequest(VecRequest r) {
  try {
    if (r.op == VecOp::Create) return createVec(r);
    if (r.op < VecOp::Create || r.op > VecOp::Drawn)
      return failVec(r, ErrorCode::BadRequest, "op", "unknown op " + std::to_string(static_cast<int>(r.op)));
    auto found = registry_.find(r.session_id);
    if (!found) return failVec(r, ErrorCode::UnknownSession, "session_id", "unknown session '" + r.session_id + "'");
    auto v = std::dynamic_pointer_cast<VecSession>(found);
    if (!v)
      return failVec(r, ErrorCode::WrongMode, "session_id",
                     "session " + r.session_id + " is not vectorised (use request_t on GROUNDSIM_REQUEST)");
    if (const OwnerCheck c = checkOwner(v.get(), r.session_id, r.token); !c) return failVec(r, c.code, "token", c.why);
    if (r.snapshot.size() > cfg_.max_snapshot_bytes)
      return failVec(r, ErrorCode::BadRequest, "snapshot",
                     std::to_string(r.snapshot.size()) + " bytes, at most " + std::to_string(cfg_.max_snapshot_bytes));
    // counts, finite actions, env and seed ranges: checked here so that a
    // bad request is refused at once, without waiting behind queued steps
    std::string field;
    const std::string why = checkVecRequest(r, v->layout(), field);
    if (!why.empty())
      return failVec(r, field.rfind("actions", 0) == 0 ? ErrorCode::BadControl : ErrorCode::BadRequest, field, why);
    v->touch(r.received == TimePoint{} ? clock_.now() : r.received);
    v->post(std::move(r));
    pool_.wake(v);
  } catch (const std::exception& e) {
    failVec(r, ErrorCode::Internal, "", std::string("internal error: ") + e.what());
  } catch (...) {
    failVec(r, ErrorCode::Internal, "", "internal error: unknown exception");
  }
}

void SessionService::createVec(const VecRequest& r) {
  if (r.scenario_json.size() > cfg_.max_scenario_bytes)
    return failVec(r, ErrorCode::BadScenario, "scenario_json",
                   std::to_string(r.scenario_json.size()) + " bytes, at most " +
                       std::to_string(cfg_.max_scenario_bytes) + " (server --max-scenario-bytes)");
  // before anything is built: the server's bound on the batch
  if (r.num_envs < 1 || r.num_envs > cfg_.max_envs)
    return failVec(r, ErrorCode::BadRequest, "num_envs",
                   std::to_string(r.num_envs) + " is outside [1, " + std::to_string(cfg_.max_envs) +
                       "] (groundsim-server --max-envs)");
  if (const OwnerCheck a = admitCreate(r.client_id); !a) return failVec(r, a.code, "", a.why);
  pool_.post([this, r] { buildVec(r); });
}

void SessionService::buildVec(const VecRequest& r) {
  std::shared_ptr<VecSession> session;
  std::string id;        // given by the registry, until the session takes it
  bool claimed = false;  // in the fleet: released again if the session is not built
  try {
    experiments::VecEnvOptions opt;
    opt.num_threads = 1;  // on this worker only: the pool shares the cores among sessions
    opt.budget = cfg_.budget;
    std::shared_ptr<const scenario::AssetBytes> assets;
    opt.files = filesFor(scenario::parseScenarioDocument(r.scenario_json, cfg_.budget), r.request_id, r.client_id,
                         &assets);
    opt.max_envs = cfg_.max_envs;
    std::unique_ptr<experiments::BatchEnv> env = experiments::makeVecEnv(r.scenario_json, r.num_envs, opt);
    // the name and vehicle names for listings (the scenario was just validated by makeVecEnv)
    const scenario::Scenario sc = scenario::parseScenario(r.scenario_json, cfg_.budget, opt.files);
    VecSetup setup;
    setup.token = newToken();
    setup.name = sc.name;
    setup.scenario_json = r.scenario_json;
    for (const auto& v : sc.vehicles) setup.vehicle_names.push_back(v.name);
    setup.assets = std::move(assets);
    const std::int64_t epoch = claimId(registry_, ownership_, r.client_id + "/" + std::to_string(r.request_id), id);
    claimed = epoch > 0;
    setup.id = id;
    session = std::make_shared<VecSession>(setup, std::move(env), out_, clock_.now(), clock_);
    session->setEpoch(epoch);
    session->setCreator(clientKey(r.client_id));
    registry_.insert(session);
    VecReply reply;
    reply.op = VecOp::Create;
    reply.request_id = r.request_id;
    reply.client_id = r.client_id;
    reply.session_id = setup.id;
    reply.token = setup.token;
    reply.num_envs = session->layout().num_envs;
    reply.obs_size = session->layout().obsSize();
    reply.sessions.push_back(session->info(clock_.now()));
    out_.publishVecReply(reply);
    return;
  } catch (const scenario::ScenarioError& e) {
    failVec(r, ErrorCode::BadScenario, "scenario_json", "invalid scenario: " + joinIssues(e));
  } catch (const MissingAssetsError& e) {
    failVec(r, ErrorCode::MissingAssets, "assets", e.what());
  } catch (const UnavailableError& e) {
    failVec(r, ErrorCode::Unavailable, "", std::string("unavailable: ") + e.what() + "; create again");
  } catch (const experiments::ExperimentError& e) {
    failVec(r, ErrorCode::BadRequest, e.field(), reasonOf(e));
  } catch (const std::bad_alloc&) {
    failVec(r, ErrorCode::BadScenario, "num_envs", "building the environments needs more memory than the server has");
  } catch (const std::exception& e) {
    failVec(r, session ? ErrorCode::Internal : ErrorCode::BadScenario, session ? "" : "scenario_json",
            std::string(session ? "internal error: " : "invalid scenario: ") + e.what());
  } catch (...) {
    failVec(r, ErrorCode::Internal, "", "internal error: unknown exception while building the environments");
  }
  if (session) return;
  const std::string client = clientKey(r.client_id);
  registry_.cancel(id, &client);
  if (claimed) ownership_->release(id);
}

}  // namespace groundsim::session
