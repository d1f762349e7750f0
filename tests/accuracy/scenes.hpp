// Shipped configs for the accuracy tests, shortened with overrides, and the
// converged reference the error measure compares against.
#pragma once

#include <string>
#include <vector>

#include "accuracy/error_measure.hpp"
#include "accuracy/pilot.hpp"
#include "accuracy/trajectory.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::accuracy::test {

inline scenario::Scenario config(const std::string& name, const std::vector<std::string>& overrides = {}) {
  const std::string dir = std::string(GROUNDSIM_CONFIGS) + "/";
  const std::string path = dir + name;
  nlohmann::json doc = scenario::loadScenarioDocument(path);
  for (const std::string& o : overrides) scenario::applyOverride(doc, o);
  return scenario::parseScenario(std::move(doc),
                                 scenario::FileAccess::local(path.substr(0, path.find_last_of('/'))));
}

// Velocity Verlet at `dt`, contact refined with it (floor: contact's need
// at 64 dt): a step far below anything the chooser takes.
inline Trajectory reference(const scenario::Scenario& s, double dt, int floor = 1) {
  return runTrajectory(withSettings(s, IntegratorKind::VelocityVerlet, dt, floor), s.duration);
}

}  // namespace groundsim::accuracy::test
