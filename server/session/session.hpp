// One hosted simulation: a Simulator, its mode and pacing, and a mailbox of
// commands. The receive thread only posts to the mailbox (a short lock); a
// worker applies the mailbox and steps the session in a bounded slice, so a
// slow or diverging scene never holds the receive loop or another session.
#pragma once

#include <atomic>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "stepping/applied.hpp"
#include "clock.hpp"
#include "stepping/frame_build.hpp"
#include "hosted.hpp"
#include "config.hpp"
#include "pacing.hpp"
#include "accuracy/live_estimate.hpp"
#include "accuracy/refinement.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"
#include "scheduler.hpp"
#include "types.hpp"

namespace groundsim::session {

// RaceGlue: stepping/race_glue.hpp
class RaceBots;  // race_bots.hpp

struct SessionSetup {
  std::string id;
  std::string token;
  std::string name;                   // scenario name
  std::string scenario_json;          // the document it was created from (Op::Scenario)
  std::vector<std::string> vehicle_names;
  double duration = 5.0;              // s; <= 0: unlimited (lockstep ignores it)
  Mode mode = Mode::Realtime;
  double rate = 1.0;
  double publish_rate = 50.0;         // Hz
  // The scenario's `vehicle.controls` time tables (one per scripted road
  // car): followed as simulated time passes, like `groundsim run`, until a
  // client sends controls_t for that car; a reset hands it back to the table.
  std::vector<scenario::ControlTable> control_tables;
  // The files its scenario named (sent with the create), kept with the
  // session: they stay in the server's asset store while it runs.
  std::shared_ptr<const scenario::AssetBytes> assets;
  // The text of the race's bot policy file (race.bot_policy), as the
  // scenario's parse read it (null: none, or the classical driver).
  std::shared_ptr<const std::string> bot_policy;
  // A scenario with a tolerance (docs/accuracy.md): the live error estimate
  // the session steps beside its simulation (null otherwise), and the
  // tolerance and refinement it is watched with (accuracy/refinement.hpp:
  // a finer step at the next safe point, or one warning event).
  std::shared_ptr<accuracy::LiveEstimate> live_estimate;
  accuracy::RefinementPolicy refinement;
};


class Session : public HostedSession {
 public:
  // `clock` gives every instant the session reads after `now` (tests pass a
  // manual one); it must outlive the session.
  Session(SessionSetup setup, std::shared_ptr<const Model> model, State initial,
          const ServiceConfig& cfg, Output& out, TimePoint now, const SessionClock& clock = steadyClock());

  const std::string& scenarioJson() const override { return setup_.scenario_json; }
  const std::string& name() const override { return setup_.name; }
  const std::vector<VehicleWheels>& vehicles() const { return vehicles_; }

  // Receive thread (then wake the session). Control requests: Reset,
  // Pause, Resume, Step, SetMode; stop() for Stop and reclamation.
  void post(const Request& r);
  void post(Drive d);
  void post(CarDrive d);
  void stop(std::optional<ReplyTo> reply, std::string reason) override;

  // Worker: applies the mailbox, then steps for at most cfg.slice of wall
  // time. Returns when to run next, or nothing to sleep until woken.
  // Never throws: a failure (even one while reporting a failure) ends the
  // session with status diverged and ERR_INTERNAL, publishes the error and
  // answers its pending step requests; later requests are still answered.
  std::optional<TimePoint> run(TimePoint now) override;
  void abandon(const char* why) noexcept override;

  // ---- a fleet (session_replica.cpp, docs/fleet.md) ----
  // The settings a standby needs to build this session again (the scenario
  // document and its settings), sent at creation and at a takeover.
  Replica scenarioReplica() const;
  // Any thread: a server joined the fleet (a standby keeps only sessions
  // whose scenario replica it heard): the session publishes its scenario
  // replica and a snapshot again, from its worker, at its next run.
  void replicateAgain() { replicate_again_ = true; }
  // Continues a session whose owner was lost, before its first run: the
  // snapshot's state, then the owner's applied entries after it (`log`,
  // seq order) replayed at their ticks, as the owner applied them; nothing
  // is published while replaying, frames and entries then continue with the
  // seqs the owner would have used; then, without new input, on to
  // `heard_tick`, the tick of the owner's last state the standby heard, so
  // that no command taken here changes a state the owner already
  // published (the frames on the way are published again, re-simulated).
  // Returns "" or why it cannot.
  std::string resume(const Replica& snapshot, const std::vector<Applied>& log, std::int64_t heard_tick = -1);


 protected:
  SessionInfo listing() const override;

 private:
  struct StepJob { ReplyTo reply; std::int64_t remaining; };
  struct StopCommand { std::optional<ReplyTo> reply; std::string reason; };
  using Command = std::variant<Request, Drive, CarDrive, StopCommand>;

  void apply(const Request& r, TimePoint now);
  void apply(const Drive& d);
  void apply(const CarDrive& d);
  void apply(const StopCommand& c);
  void failSteps(ErrorCode code, const std::string& why);
  void diverged(const std::string& why, ErrorCode code);
  void failSafely(const char* what) noexcept;
  std::optional<TimePoint> advance(TimePoint now, TimePoint deadline);
  std::optional<TimePoint> advanceLockstep(TimePoint deadline);
  bool stepOnce();
  void reportHits();
  void watchAccuracy();  // after a step, with the live estimate
  // Publishes an entry of the applied-command log (applied.hpp), at the
  // current tick, kept with the frame published next.
  void logApplied(Applied a);
  bool emitFrame(TimePoint now);   // false: out of publish budget, retry later
  void publishFrame();             // now, whatever the budget (final and lockstep frames)
  Frame makeFrame(bool published = true);
  void reply(const ReplyTo& to, bool ok, ErrorCode code, std::string error,
             std::optional<Frame> state = std::nullopt);
  void event(Severity sev, ErrorCode code, std::string reason);
  void checkCommandTimeout(TimePoint now);
  void releaseHeld(TimePoint now);    // every vehicle's hold forgotten (a reset), timeouts from now
  struct Held;
  // One vehicle's hold past the timeout: released, logged, warned of.
  template <class Release>
  void expire(Held& h, TimePoint now, size_t v, AppliedKind kind, const char* command, const char* what,
              Release release);
  void reanchor(TimePoint now);
  void updateInfo(TimePoint now);
  bool finished() const;
  void replicate();  // a Snapshot replica now (worker)
  std::string replay(const Applied& a);
  std::string fastForward(std::int64_t tick);
  // race_glue.cpp: the scenario's race, when it has one (else they return at once)
  void raceBeforeStep();
  void raceAfterStep(double t0);
  void raceReset();
  void raceRespawn(const Request& r);  // OP_RESET with steps = -1 - vehicle
  void respawnVehicle(int v);          // a player's respawn or a lost bot's
  void botsDrive();  // race_bots.hpp: the bots' commands, applied as players' are

  SessionSetup setup_;
  const ServiceConfig& cfg_;
  Output& out_;
  const SessionClock& clock_;
  Simulator sim_;
  accuracy::Refiner refiner_;  // with the live estimate: refines or warns (watchAccuracy)
  State initial_;
  std::vector<VehicleWheels> vehicles_;
  std::shared_ptr<const std::vector<std::string>> names_;
  std::int64_t steps_per_frame_ = 1;
  std::int64_t replica_every_ = 0;   // ticks between snapshots for the standbys; 0: none
  bool replaying_ = false;           // resume(): nothing is published
  std::shared_ptr<RaceGlue> race_;    // null: no race
  std::shared_ptr<RaceBots> bots_;    // null: no bots

  // worker-owned
  Status status_ = Status::Running;
  std::string reason_;
  std::int64_t seq_ = 0;
  bool frame_pending_ = true;         // the initial state is the first frame
  bool replica_due_ = false;          // a snapshot for the standbys once this tick's frame is out
  std::atomic<bool> replicate_again_{false};  // replicateAgain()
  RealtimeAnchor anchor_;
  PublishBudget budget_;
  std::deque<StepJob> steps_;
  TimePoint last_drive_{};            // the newest drive command of any vehicle (the latency trace)
  TimePoint drive_applied_{};  // when last_drive_'s command was applied
  // Per vehicle: its driver's last command and whether it holds a torque or
  // a pedal. Each vehicle's controls expire on their own (checkCommandTimeout):
  // another player's commands neither refresh nor release them.
  struct Held {
    TimePoint last{};
    bool held = false;
  };
  std::vector<Held> drive_held_;      // drive_t (wheel torques)
  std::vector<Held> car_held_;        // controls_t (a road car's throttle and brake)
  DrivenCars cars_;                   // per road car: a client took over from the control table
  std::int64_t applied_seq_ = 0;      // entries of the applied-command log so far
  TimePoint last_overrun_event_{};
  std::vector<Command> work_;

  // shared with the receive thread
  mutable std::mutex mailbox_mutex_;
  std::vector<Command> mailbox_;
  mutable std::mutex info_mutex_;
  SessionInfo info_;
};

}  // namespace groundsim::session
