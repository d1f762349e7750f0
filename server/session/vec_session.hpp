// A vectorised session: N environments of one task (experiments::BatchEnv
// from makeVecEnv, on the calling thread only), driven by VecRequests. It is
// a Task of the scheduler like every session: the receive thread posts to
// its mailbox, a worker carries out one request per run (one request -> one
// batched step -> one reply) and yields, so sessions due meanwhile take
// their turn between two batched steps. It publishes no state_t: its
// results go back in the replies.
#pragma once

#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "clock.hpp"
#include "config.hpp"
#include "pacing.hpp"
#include "experiments/batch_env.hpp"
#include "hosted.hpp"
#include "scheduler.hpp"
#include "types.hpp"

namespace groundsim::session {

struct VecSetup {
  std::string id;
  std::string token;
  std::string name;                   // scenario name
  std::string scenario_json;
  std::vector<std::string> vehicle_names;
  std::shared_ptr<const scenario::AssetBytes> assets;  // as SessionSetup::assets
};

class VecSession : public HostedSession {
 public:
  VecSession(VecSetup setup, std::unique_ptr<experiments::BatchEnv> env, Output& out, TimePoint now,
             const SessionClock& clock = steadyClock());

  const std::string& name() const override { return setup_.name; }
  const std::string& scenarioJson() const override { return setup_.scenario_json; }
  const experiments::Layout& layout() const { return *layout_; }

  // Receive thread (then wake the session); requests checked by the service.
  void post(VecRequest r);
  void stop(std::optional<ReplyTo> reply, std::string reason) override;

  std::optional<TimePoint> run(TimePoint now) override;
  void abandon(const char* why) noexcept override;


 protected:
  SessionInfo listing() const override;

 private:
  struct StopCommand { std::optional<ReplyTo> reply; std::string reason; };
  using Command = std::variant<VecRequest, StopCommand>;

  void apply(const VecRequest& r);
  void apply(const StopCommand& c);
  VecReply replyFor(const VecRequest& r) const;
  void refuse(const VecRequest& r, ErrorCode code, const std::string& field, const std::string& error);
  void fillEnvs(VecReply& reply, int begin, int count, const float* obs) const;
  void updateInfo();

  VecSetup setup_;
  Output& out_;
  const SessionClock& clock_;
  std::unique_ptr<experiments::BatchEnv> env_;
  std::shared_ptr<const experiments::Layout> layout_;

  // worker-owned
  Status status_ = Status::Running;
  std::string reason_;
  std::int64_t tick_ = 0;
  std::vector<float> obs_;
  std::vector<double> rewards_;
  std::vector<std::uint8_t> terminated_, truncated_;

  mutable std::mutex mailbox_mutex_;
  std::deque<Command> mailbox_;
  mutable std::mutex info_mutex_;
  SessionInfo info_;
};

// "" when the request fits the session (counts, finite actions, env index,
// seed range, snapshot size), else sets field and returns the reason.
// An ExperimentError's reason without its "field: " prefix.
std::string reasonOf(const experiments::ExperimentError& e);

std::string checkVecRequest(const VecRequest& r, const experiments::Layout& layout, std::string& field);

}  // namespace groundsim::session
