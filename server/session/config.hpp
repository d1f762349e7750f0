// Limits and timings of the session service (groundsim-server's options).
#pragma once

#include <cstdint>
#include <cstddef>

#include <string>

#include "asset_store.hpp"
#include "scenario/budget.hpp"

namespace groundsim::session {

struct ServiceConfig {
  int workers = 0;                     // stepping threads; 0: one per core
  int max_sessions = 64;               // concurrent sessions, pending creates included
  // One client's share (by the client_id of its creates; docs/reliability.md,
  // Fairness): sessions it may hold at once, and creates a minute (a burst
  // of that many, then one every 60 / n s). 0: no limit.
  int max_client_sessions = 16;
  double client_creates_per_minute = 60.0;
  double idle_timeout = 600.0;         // s  wall time without owner activity before a session is reclaimed
  double command_timeout = 0.5;        // s  real time mode: drive torques fall to zero without a fresh command
  double max_torque = 1000.0;          // N m  largest |drive| or brake torque accepted
  double slice = 0.002;                // s  wall time one session may step before yielding its worker
  double publish_limit = 2000.0;       // frames per wall second per session (paced, never dropped)
  double max_lag = 0.5;                // s  real time mode: a session this far behind re-anchors (overrun event)
  int max_vehicles = 32;               // per session: keeps a state message in one UDP datagram
  std::size_t max_scenario_bytes = 1 << 20;  // at most net::kMaxScenarioBytes (what a create can carry)
  std::int64_t max_steps_per_request = 100'000'000;
  int max_envs = 1024;                 // environments of one vectorised session (checked before building)
  std::size_t max_snapshot_bytes = 1 << 20;  // a restore request's snapshot (at most net::kMaxSnapshotBytes)
  double min_rate = 1e-3;              // smallest real-time factor (create, mode)
  double max_rate = 1000.0;            // largest real-time factor
  double min_publish_rate = 1e-3;      // Hz of simulation time
  double max_publish_rate = 10000.0;   // Hz of simulation time
  int max_build_jobs = 0;              // scene builds at once; 0: workers - 1 (at least 1)
  double ended_linger = 10.0;          // s  a stopped or reclaimed session stays in the heartbeat, so that
                                       //    subscribers learn its last seq even when its final state is lost
  // A fleet (docs/fleet.md): every real-time, fast or lockstep session sends
  // its standbys a snapshot every this many seconds of simulated time; 0
  // (a lone server): none.
  double replica_interval = 0.0;
  // The model budget every create is validated against before anything is
  // built (scenario/budget.hpp); the service also holds its max_vehicles and
  // max_document_bytes to the two fields above, whichever is smaller.
  scenario::Budget budget = serverBudget();
  // Where a scenario's files (heightfields, friction maps) may be read:
  // relative paths inside this folder only (no absolute path, no "..", no
  // symlink leading out), since scenarios come from remote clients; "": none.
  std::string terrain_dir;
  // The files clients send with their scenarios (asset_store.hpp): a create
  // builds from these, checked by hash, never from this server's disk
  // (except a name not among them, under terrain_dir).
  AssetLimits assets;

  static scenario::Budget serverBudget() {
    scenario::Budget b;
    b.source = "groundsim-server";
    return b;
  }
};

}  // namespace groundsim::session
