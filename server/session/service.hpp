// The session service: the registry of sessions, ownership checks, input
// validation and the worker pool. Transport-neutral: the LCM adapter calls
// handleRequest/handleDrive from its receive thread and implements Output.
// Every request is answered (reply, plus an event when it is refused); no
// exception leaves this class.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "config.hpp"
#include "create_rate.hpp"
#include "ownership.hpp"
#include "registry.hpp"
#include "scheduler.hpp"
#include "session.hpp"
#include "types.hpp"
#include "vec_session.hpp"

namespace groundsim::session {

struct ServiceStatus {
  int workers = 0;
  int max_sessions = 0;
  double load = 0.0;
  std::vector<SessionInfo> sessions;
  // Stopped or reclaimed in the last cfg.ended_linger seconds, with their
  // final status and last seq (the heartbeat lists them; `list` does not).
  std::vector<SessionInfo> ended;
};

class SessionService {
 public:
  // `clock` is every session's (tests pass a manual one); it must outlive the service.
  SessionService(ServiceConfig cfg, Output& out, const SessionClock& clock = steadyClock());
  ~SessionService();

  // Receive thread only.
  void handleRequest(const Request& r);
  void handleDrive(Drive d);
  // Normalized controls of a road car (controls_t): refused with an event
  // naming the field for a vehicle that is not a road car or a value that
  // is not finite or out of range.
  void handleControls(CarDrive d);
  // A request to a vectorised session (or the create of one): answered
  // with a VecReply (publishVecReply), refusals naming the field.
  void handleVecRequest(VecRequest r);
  // One part of a file sent with a scenario (asset_part_t on `channel`); a
  // part refused, or an asset whose bytes do not match its hash, is
  // answered with an error event to its client naming the file.
  void handleAssetPart(const AssetPart& p, const std::string& channel);
  // Input the transport could not decode (names the channel and why).
  void reportBadInput(ErrorCode code, const std::string& channel, const std::string& reason);
  // Reclaims idle sessions; call about once a second.
  void housekeeping();
  ServiceStatus status();
  // Stops every session (each publishes a final stopped frame) and the pool.
  void shutdown(const std::string& reason);

  const ServiceConfig& config() const { return cfg_; }

  // ---- a fleet (docs/fleet.md) ----
  // Before the first request: who claims session ids (null: a lone server).
  void setOwnership(Ownership* o) { ownership_ = o; }
  // Hosts a session whose owner was lost, from its replicas: built from the
  // scenario replica (its files from this server's asset store), resumed at
  // the snapshot with the owner's applied entries after it, under `epoch`.
  // Returns "" or why not (the caller releases its claim then).
  std::string adopt(const Replica& scenario, const Replica& snapshot, const std::vector<Applied>& log, std::int64_t heard_tick,
                    std::int64_t epoch);
  // A server joined the fleet: every hosted real time, fast or lockstep
  // session replicates its scenario and a snapshot again (Session::replicateAgain).
  void replicateAgain();
  // Forgets a session another server owns now; nothing is published for it
  // (the transport drops its messages) and its claim is not released.
  void disown(const std::string& id);
  // The ids of the sessions hosted here, of every kind.
  std::vector<std::string> hostedIds() const;

 private:
  // The files a create's document names, from the store: every asset of its
  // manifest must be here (pinned into *held for the session's life). When
  // some are missing, publishes an AssetWant for each and throws
  // MissingAssetsError; a manifest beyond the limits throws ScenarioError.
  scenario::FileAccess filesFor(const nlohmann::json& doc, std::int64_t request_id, const std::string& client_id,
                                std::shared_ptr<const scenario::AssetBytes>* held);
  void create(const Request& r);
  void build(const Request& r);  // on a worker
  void createVec(const VecRequest& r);
  void buildVec(const VecRequest& r);  // on a worker
  void failVec(const VecRequest& r, ErrorCode code, const std::string& field, const std::string& error) noexcept;
  // Looks up the session and checks the token; answers the refusal itself.
  std::shared_ptr<HostedSession> owned(const Request& r);
  void stop(const Request& r);
  bool validSettings(const Request& r);
  void fail(const Request& r, ErrorCode code, const std::string& error) noexcept;
  void replyOk(const Request& r, Reply reply);

  ServiceConfig cfg_;
  Output& out_;
  const SessionClock& clock_;
  Ownership* ownership_ = nullptr;
  Registry registry_;  // every session, of both kinds (workers insert what they build)
  CreateRate create_rate_;  // creates per minute per client (receive thread)
  OwnerCheck admitCreate(const std::string& client_id);  // receive thread
  // The principal a client's sessions and creates are counted under: the
  // id up to its first '/' (protocol/client_id.hpp: one user on one host).
  static std::string clientKey(const std::string& client_id) {
    return client_id.empty() ? "(no client id)" : client_id.substr(0, client_id.find('/'));
  }
  AssetStore assets_;
  Scheduler pool_;    // last member: its workers stop before the registry goes
};

}  // namespace groundsim::session
