// Re-simulation of a recorded session (docs/logging.md, Re-simulation): the
// scenario built as the server builds it, then the applied-command log
// (applied.hpp) replayed at the ticks the session applied it, through the
// same functions, stepping as Session::stepOnce does (a race's countdown,
// go and respawns included: race_glue.hpp). On the same machine
// and build this reaches the same states bit for bit; `groundsim replay
// --resimulate` compares them with the recorded ones.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stepping/applied.hpp"
#include "stepping/frame_build.hpp"
#include "stepping/race_glue.hpp"
#include "scenario/file_access.hpp"
#include "scenario/scenario.hpp"
#include "stepping/types.hpp"

namespace groundsim::stepping {

class Resimulator {
 public:
  // Throws scenario::ScenarioError (invalid scenario, missing files) as the
  // server's create would.
  Resimulator(const std::string& scenario_json, const scenario::FileAccess& files);

  // Applies one entry of the log: steps up to the tick it took effect at,
  // then applies it. Returns "" or why it cannot (its tick is behind the
  // simulation's without a reset, or the simulation diverged before it).
  std::string apply(const Applied& a);
  // Steps up to `tick`. Returns "" or why it cannot.
  std::string stepTo(std::int64_t tick);
  // The frame now (physics fields; the caller sets id, seq, mode, status).
  Frame frame() const;

  std::int64_t tick() const { return sim_.state().tick; }
  bool diverged() const { return diverged_; }

 private:
  bool stepOnce();

  // built before sim_ (its initializer fills them)
  State initial_;
  std::vector<scenario::ControlTable> tables_;
  std::shared_ptr<const std::vector<std::string>> names_;
  Simulator sim_;
  std::vector<VehicleWheels> vehicles_;
  DrivenCars cars_;
  std::unique_ptr<RaceGlue> race_;  // the scenario's race, stepped as the session steps it; null: none
  bool diverged_ = false;
};

}  // namespace groundsim::stepping
