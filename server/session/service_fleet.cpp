// SessionService in a fleet (docs/fleet.md): adopting a session whose owner
// was lost, disowning one, replicating again.
#include "service.hpp"

#include <string>
#include <vector>

#include "scenario/scenario.hpp"
#include "service_detail.hpp"

namespace groundsim::session {
using service_detail::joinIssues;

// ---- a fleet ----------------------------------------------------------------

std::vector<std::string> SessionService::hostedIds() const { return registry_.ids(); }

void SessionService::disown(const std::string& id) {
  if (auto s = registry_.retire(id, clock_.now())) {
    s->stop(std::nullopt, "taken over by another server");
    pool_.wake(s);
  }
}

void SessionService::replicateAgain() {
  for (const std::string& id : registry_.ids())
    if (auto s = registry_.find<Session>(id)) {
      s->replicateAgain();
      pool_.wake(s);
    }
}

std::string SessionService::adopt(const Replica& scenario, const Replica& snapshot, const std::vector<Applied>& log,
                                  std::int64_t heard_tick,
                                  std::int64_t epoch) {
  const std::string& id = scenario.session_id;
  try {
    if (registry_.find(id)) return "session " + id + " is hosted here already";
    if (const OwnerCheck a = registry_.admit(cfg_.max_sessions); !a) return a.why;
    std::shared_ptr<Session> session;
    try {
      const nlohmann::json meta = nlohmann::json::parse(scenario.meta);
      nlohmann::json doc = scenario::parseScenarioDocument(scenario.data, cfg_.budget);
      std::shared_ptr<const scenario::AssetBytes> assets;
      const scenario::FileAccess files = filesFor(doc, 0, "", &assets);
      const scenario::Scenario sc = scenario::parseScenario(std::move(doc), cfg_.budget, files);
      scenario::Scene scene = scenario::buildScene(sc);
      const int nveh = static_cast<int>(scene.built.model->vehicle_names.size());
      SessionSetup setup;
      setup.id = id;
      setup.token = meta.at("token").get<std::string>();
      setup.name = sc.name;
      setup.scenario_json = scenario.data;
      if (sc.race) setup.bot_policy = sc.race->bot_policy_text;
      setup.vehicle_names = scene.vehicle_names.size() == static_cast<size_t>(nveh) ? scene.vehicle_names
                                                                                   : scene.built.model->vehicle_names;
      setup.duration = meta.value("duration", scene.duration);
      setup.mode = modeFromInt(meta.value("mode", 1)).value_or(Mode::Realtime);
      setup.rate = meta.value("rate", 1.0);
      setup.publish_rate = meta.value("publish_rate", scene.output_rate);
      setup.control_tables = scene.control_tables;
      setup.assets = std::move(assets);
      session = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg_, out_, clock_.now(),
                                          clock_);
      session->setEpoch(epoch);
      if (std::string why = session->resume(snapshot, log, heard_tick); !why.empty()) {
        registry_.cancel();
        return "cannot resume session " + id + ": " + why;
      }
    } catch (const scenario::ScenarioError& e) {
      registry_.cancel();
      return "cannot rebuild session " + id + ": " + joinIssues(e);
    } catch (const std::exception& e) {
      registry_.cancel();
      return "cannot rebuild session " + id + ": " + e.what();
    }
    registry_.insert(session);
    out_.publishReplica(session->scenarioReplica());  // the standbys learn the new owner and epoch
    pool_.wake(session);
    return "";
  } catch (const std::exception& e) {
    return std::string("internal error: ") + e.what();
  }
}

}  // namespace groundsim::session
