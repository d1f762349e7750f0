// SessionService's insides, shared by its source files and by nothing else:
// service.cpp (requests, creates, controls, upkeep), service_vec.cpp
// (vectorised sessions) and service_fleet.cpp (a fleet: adopt, disown).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "ownership.hpp"
#include "registry.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::session::service_detail {

// The scenario layer caps the list (the first 20, then "and N more") and
// quotes user strings.
std::string joinIssues(const scenario::ScenarioError& e);

// A create whose assets are not all here yet (the wants are published).
struct MissingAssetsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A fresh id and this server's claim on it: the registry's id, claimed in
// the fleet when there is one (another server may hold it: draw again).
std::int64_t claimId(Registry& registry, Ownership* ownership, const std::string& placement, std::string& id);

}  // namespace groundsim::session::service_detail
