#include "stepping/resimulate.hpp"

#include "scenario/scenario.hpp"

namespace groundsim::stepping {
namespace {

Simulator build(const std::string& json, const scenario::FileAccess& files, State* initial,
                std::vector<scenario::ControlTable>* tables, std::vector<std::string>* names) {
  // as SessionService::build
  const scenario::Scenario sc = scenario::parseScenario(scenario::parseScenarioDocument(json), files);
  scenario::Scene scene = scenario::buildScene(sc);
  *initial = scene.built.initial;
  *tables = scene.control_tables;
  const auto nveh = scene.built.model->vehicle_names.size();
  *names = scene.vehicle_names.size() == nveh ? scene.vehicle_names : scene.built.model->vehicle_names;
  return Simulator(scene.built.model, scene.built.initial);
}

}  // namespace

Resimulator::Resimulator(const std::string& scenario_json, const scenario::FileAccess& files)
    : sim_([&] {
        std::vector<std::string> names;
        Simulator s = build(scenario_json, files, &initial_, &tables_, &names);
        names_ = std::make_shared<const std::vector<std::string>>(std::move(names));
        return s;
      }()) {
  vehicles_ = vehicleWheels(sim_.model());
  race_ = makeRaceGlue(scenario_json, sim_.modelPtr());
}

bool Resimulator::stepOnce() {
  if (!tables_.empty()) followControlTables(sim_, cars_, tables_);
  if (race_) raceHold(*race_, sim_);
  const double t0 = sim_.state().t;
  if (!sim_.step()) {
    diverged_ = true;
    return false;
  }
  if (race_) raceStepped(*race_, sim_, t0);
  if (sim_.model().collisions) sim_.takeEndedHits();
  return true;
}

std::string Resimulator::stepTo(std::int64_t tick) {
  if (tick < sim_.state().tick)
    return "tick " + std::to_string(tick) + " is behind the re-simulation's " + std::to_string(sim_.state().tick) +
           " and no reset in the log explains it";
  while (sim_.state().tick < tick) {
    if (diverged_) return "the re-simulation diverged at tick " + std::to_string(sim_.state().tick) + ": " +
                          sim_.state().health_reason;
    if (!stepOnce()) continue;  // reported on the next turn
  }
  return "";
}

std::string Resimulator::apply(const Applied& a) {
  if (std::string why = stepTo(a.tick); !why.empty()) return why;
  if (std::string why = applyEntry(sim_, cars_, vehicles_, initial_, a, race_.get()); !why.empty()) return why;
  if (a.kind == AppliedKind::Reset) diverged_ = false;
  return "";
}

Frame Resimulator::frame() const {
  Frame f;
  f.names = names_;
  fillFrame(f, sim_, vehicles_);
  return f;
}

}  // namespace groundsim::stepping
