// Hits between bodies as a game or a task sees them: a pair of collision
// groups from first touch to separation, with where, how hard and the
// impulse exchanged. Telemetry, kept by the Simulator beside the state (not
// part of it: a restored state starts with no hit under way).
#pragma once

#include <cstddef>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/workspace.hpp"

namespace groundsim {

struct Hit {
  int a = -1, b = -1;               // collision groups (Model::groups), a < b
  double begin = 0.0, end = 0.0;    // s      first and last step in contact
  double impulse = 0.0;             // N s    |integral of the force on a| so far
  double peak_force = 0.0;          // N
  double closing_speed = 0.0;       // m/s    approach speed of the reference bodies at first touch
  double depth = 0.0;               // m      deepest probe so far
  Vec3 where = Vec3::Zero();        // m      last contact centroid
  Vec3 momentum = Vec3::Zero();     // N s    integral of the force on a
  Vec3 force = Vec3::Zero();        // N      on a, by b, at the last step
  bool hard = false;                // impulse / lighter mass above collision.hard_impact_dv (collision.hpp)
};

class ContactLog {
 public:
  // After a step: pairs still in contact accumulate, new ones start, the
  // others end (kept for takeEnded(), at most kMaxEnded, the oldest dropped
  // first and counted).
  void update(const Model& m, const State& s, const Workspace& ws, double dt);
  const std::vector<Hit>& active() const { return active_; }
  // Hits that ended since the last call.
  std::vector<Hit> takeEnded();
  std::size_t dropped() const { return dropped_; }
  void clear();

  static constexpr std::size_t kMaxEnded = 256;

 private:
  std::vector<Hit> active_, ended_, next_;
  std::size_t dropped_ = 0;
};

}  // namespace groundsim
