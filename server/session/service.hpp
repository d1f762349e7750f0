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
  std::shared_ptr<VecSession> findVec(const std::string& id);
  bool stopVec(const Request& r);  // Op::Stop of a vectorised session; false: not one
  std::string uniqueId();          // mutex_ held
  std::shared_ptr<Session> find(const std::string& id);
  // Looks up the session and checks the token; answers the refusal itself.
  std::shared_ptr<Session> owned(const Request& r);
  bool validSettings(const Request& r);
  void fail(const Request& r, ErrorCode code, const std::string& error) noexcept;
  void retire(std::shared_ptr<Session> s);  // mutex_ held: into ended_
  void retire(std::shared_ptr<VecSession> s);
  void replyOk(const Request& r, Reply reply);

  ServiceConfig cfg_;
  Output& out_;
  const SessionClock& clock_;
  std::mutex mutex_;  // sessions_ and reserved_ (workers add sessions after building them)
  std::map<std::string, std::shared_ptr<Session>> sessions_;
  std::map<std::string, std::shared_ptr<VecSession>> vecs_;  // vectorised sessions
  struct Ended {
    std::shared_ptr<Session> session;
    std::shared_ptr<VecSession> vec;  // one of the two
    TimePoint since;
  };
  std::vector<Ended> ended_;
  int reserved_ = 0;  // creates accepted but still building
  bool shut_down_ = false;
  AssetStore assets_;
  Scheduler pool_;    // last member: its workers stop before the registry goes
};

}  // namespace groundsim::session
