#include "stepping/applied.hpp"

#include <algorithm>

#include "stepping/race_glue.hpp"

namespace groundsim::stepping {

const char* appliedKindName(AppliedKind k) {
  switch (k) {
    case AppliedKind::Drive: return "drive";
    case AppliedKind::Controls: return "controls";
    case AppliedKind::DriveTimeout: return "drive_timeout";
    case AppliedKind::ControlsTimeout: return "controls_timeout";
    case AppliedKind::Reset: return "reset";
    case AppliedKind::Pause: return "pause";
    case AppliedKind::Resume: return "resume";
    case AppliedKind::Step: return "step";
    case AppliedKind::SetMode: return "set_mode";
    case AppliedKind::Stop: return "stop";
    case AppliedKind::End: return "end";
    case AppliedKind::Respawn: return "respawn";
    case AppliedKind::Refine: return "refine";
  }
  return "?";
}

void applyDrive(Simulator& sim, const std::vector<int>& wheels, const std::vector<WheelControl>& applied) {
  auto& controls = sim.controls();
  for (size_t k = 0; k < wheels.size() && k < applied.size(); ++k) controls[wheels[k]] = applied[k];
}

void applyCarControls(Simulator& sim, DrivenCars& cars, int road_car, const CarControls& applied) {
  sim.setCarControls(road_car, applied);
  if (cars.driven.size() <= static_cast<size_t>(road_car)) cars.driven.resize(static_cast<size_t>(road_car) + 1, false);
  cars.driven[static_cast<size_t>(road_car)] = true;  // the client drives now, not the scenario's table
}

namespace {
bool vehicleInRange(const Model& m, int v) { return v >= 0 && v < static_cast<int>(m.vehicle_names.size()); }
}  // namespace

void releaseDrive(Simulator& sim) {
  const Model& m = sim.model();
  for (size_t w = 0; w < m.wheels.size(); ++w) {
    if (!vehicleInRange(m, m.vehicle_of_wheel[w])) continue;
    sim.controls()[w].drive_torque = 0.0;
    sim.controls()[w].brake_torque = 0.0;
  }
}

void releasePedals(Simulator& sim) {
  const Model& m = sim.model();
  for (size_t c = 0; c < m.road_cars.size(); ++c) {
    if (!vehicleInRange(m, m.road_cars[c].vehicle)) continue;
    releasePedals(sim, static_cast<int>(c));
  }
}

void releaseDrive(Simulator& sim, const std::vector<int>& wheels) {
  for (int w : wheels) {
    sim.controls()[static_cast<size_t>(w)].drive_torque = 0.0;
    sim.controls()[static_cast<size_t>(w)].brake_torque = 0.0;
  }
}

void releasePedals(Simulator& sim, int road_car) {
  CarControls cc = sim.carControls(road_car);
  cc.throttle = 0.0;
  cc.brake = 0.0;
  sim.setCarControls(road_car, cc);
}

bool holdsTorque(const std::vector<WheelControl>& wheels) {
  return std::any_of(wheels.begin(), wheels.end(),
                     [](const WheelControl& c) { return c.drive_torque != 0.0 || c.brake_torque != 0.0; });
}

bool holdsPedal(const CarControls& c) { return c.throttle != 0.0 || c.brake != 0.0; }

void resetTo(Simulator& sim, DrivenCars& cars, const State& initial) {
  sim.restore(initial);
  cars.driven.assign(cars.driven.size(), false);
}

std::string applyEntry(Simulator& sim, DrivenCars& cars, const std::vector<VehicleWheels>& vehicles,
                       const State& initial, const Applied& a, RaceGlue* race) {
  const VehicleWheels* v =
      a.vehicle >= 0 && a.vehicle < static_cast<int>(vehicles.size()) ? &vehicles[a.vehicle] : nullptr;
  switch (a.kind) {
    case AppliedKind::Drive:
      if (!v) return "drive of vehicle " + std::to_string(a.vehicle) + ", which the scenario does not have";
      applyDrive(sim, v->wheels, a.wheels);
      break;
    case AppliedKind::Controls:
      if (!v || v->road_car < 0)
        return "controls of vehicle " + std::to_string(a.vehicle) + ", which is not a road car of the scenario";
      applyCarControls(sim, cars, v->road_car, a.controls);
      break;
    // a vehicle's own timeout; -1: every vehicle's (logs written before per-car timeouts)
    case AppliedKind::DriveTimeout:
      if (a.vehicle < 0) releaseDrive(sim);
      else if (v) releaseDrive(sim, v->wheels);
      else return "drive timeout of vehicle " + std::to_string(a.vehicle) + ", which the scenario does not have";
      break;
    case AppliedKind::ControlsTimeout:
      if (a.vehicle < 0) releasePedals(sim);
      else if (v && v->road_car >= 0) releasePedals(sim, v->road_car);
      else return "controls timeout of vehicle " + std::to_string(a.vehicle) + ", which is not a road car of the scenario";
      break;
    case AppliedKind::Reset:
      resetTo(sim, cars, initial);
      if (race) raceRestart(*race, sim);
      break;
    case AppliedKind::Respawn:
      if (!race) return "respawn of vehicle " + std::to_string(a.vehicle) + " in a scenario without a race";
      if (a.vehicle < 0 || a.vehicle >= race->race.cars())
        return "respawn of vehicle " + std::to_string(a.vehicle) + ", which the race does not have";
      raceRespawnCar(*race, sim, initial, a.vehicle);
      break;
    case AppliedKind::Refine: {
      // a session's refinement doubles the substeps (accuracy/refinement.hpp)
      const int now = sim.model().opt.substeps;
      if (a.steps != 2LL * now || a.steps > Simulator::kMaxSubsteps)
        return "refine to " + std::to_string(a.steps) + " substeps from " + std::to_string(now) +
               ": a refinement doubles them, to at most " + std::to_string(Simulator::kMaxSubsteps);
      sim.refine(static_cast<int>(a.steps));
      break;
    }
    // no effect on the simulation: the states they publish come with their ticks
    case AppliedKind::Pause:
    case AppliedKind::Resume:
    case AppliedKind::Step:
    case AppliedKind::SetMode:
    case AppliedKind::Stop:
    case AppliedKind::End:
      break;
  }
  return "";
}

void followControlTables(Simulator& sim, const DrivenCars& cars, const std::vector<scenario::ControlTable>& tables) {
  for (const scenario::ControlTable& ct : tables) {
    const auto car = static_cast<size_t>(ct.road_car);
    if (car < cars.driven.size() && cars.driven[car]) continue;
    if (const scenario::TimedControls* row = scenario::rowInForce(ct, sim.state().t, sim.model().opt.dt))
      sim.setCarControls(ct.road_car, row->controls);
  }
}

}  // namespace groundsim::stepping
