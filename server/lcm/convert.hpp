// Wire types (lcmtypes/) <-> session types. The only place that knows both.
#pragma once

#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>
#include <groundsim/server_status_t.hpp>
#include <groundsim/session_info_t.hpp>
#include <groundsim/state_t.hpp>

#include "physics/telemetry.hpp"
#include "session/types.hpp"

namespace groundsim::net {

inline std::int64_t toUtime(double t) { return static_cast<std::int64_t>(std::llround(t * 1e6)); }

session::Request fromMessage(const groundsim::request_t& m);
session::Drive fromMessage(const groundsim::drive_t& m);

groundsim::state_t toMessage(const session::Frame& f);
groundsim::reply_t toMessage(const session::Reply& r, std::int64_t seq);
groundsim::event_t toMessage(const session::Event& e, std::int64_t seq);
groundsim::session_info_t toMessage(const session::SessionInfo& s);

// A received state as the VehicleSample `groundsim run` writes to CSV.
VehicleSample toSample(const groundsim::state_t& m, int vehicle);

}  // namespace groundsim::net
