// In-process doubles for the session layer: a clock the test moves by hand
// (optionally ticking a little on every read, so that wall-time slices end)
// and an Output that records what a session publishes, and can be told to
// throw to exercise the error paths.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenario/scenario.hpp"
#include "session/clock.hpp"
#include "session/asset_store.hpp"
#include "stepping/applied.hpp"
#include "session/types.hpp"

namespace groundsim::session::test {

// Far from the steady clock's real readings, so code that reads the real
// clock instead of the injected one gets visibly wrong answers.
inline const TimePoint kEpoch = TimePoint{} + std::chrono::hours(24 * 365 * 50);

class ManualClock final : public SessionClock {
 public:
  explicit ManualClock(Clock::duration tick = Clock::duration::zero()) : tick_(tick) {}
  TimePoint now() const override {
    std::lock_guard<std::mutex> lk(m_);
    const TimePoint t = now_;
    now_ += tick_;
    return t;
  }
  void set(TimePoint t) {
    std::lock_guard<std::mutex> lk(m_);
    now_ = t;
  }
  void advance(double s) {
    std::lock_guard<std::mutex> lk(m_);
    now_ += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

 private:
  mutable std::mutex m_;
  mutable TimePoint now_ = kEpoch;
  Clock::duration tick_;
};

class RecordingOutput final : public Output {
 public:
  void publishState(const Frame& f) override {
    if (throw_on_state) throw std::runtime_error("state channel broken");
    std::lock_guard<std::mutex> lk(m_);
    frames.push_back(f);
  }
  void publishReply(const Reply& r) override {
    {
      std::lock_guard<std::mutex> lk(m_);
      replies.push_back(r);
    }
    cv_.notify_all();
  }
  void publishEvent(const Event& e) override {
    std::lock_guard<std::mutex> lk(m_);
    events.push_back(e);
  }
  void publishApplied(const Applied& a) override {
    std::lock_guard<std::mutex> lk(m_);
    applied.push_back(a);
  }
  void publishReplica(const Replica& r) override {
    std::lock_guard<std::mutex> lk(m_);
    replicas.push_back(r);
  }
  void publishAssetWant(const AssetWant& w) override {
    std::lock_guard<std::mutex> lk(m_);
    asset_wants.push_back(w);
  }
  void publishVecReply(const VecReply& r) override {
    {
      std::lock_guard<std::mutex> lk(m_);
      vec_replies.push_back(r);
    }
    cv_.notify_all();
  }
  // Waits (bounded; the verdict never depends on how long) for the vec reply to request_id.
  bool waitVecReply(std::int64_t request_id, VecReply* out, double timeout_s = 60) {
    std::unique_lock<std::mutex> lk(m_);
    const bool got = cv_.wait_for(lk, std::chrono::duration<double>(timeout_s), [&] {
      for (const auto& r : vec_replies)
        if (r.request_id == request_id) return true;
      return false;
    });
    if (got)
      for (const auto& r : vec_replies)
        if (r.request_id == request_id) *out = r;
    return got;
  }
  // Waits (bounded; the verdict never depends on how long) for a reply to request_id.
  bool waitReply(std::int64_t request_id, Reply* out, double timeout_s = 60) {
    std::unique_lock<std::mutex> lk(m_);
    const bool got = cv_.wait_for(lk, std::chrono::duration<double>(timeout_s), [&] {
      for (const auto& r : replies)
        if (r.request_id == request_id) return true;
      return false;
    });
    if (got)
      for (const auto& r : replies)
        if (r.request_id == request_id) *out = r;
    return got;
  }
  int eventsWith(ErrorCode code) const {
    std::lock_guard<std::mutex> lk(m_);
    int n = 0;
    for (const auto& e : events) n += e.code == code;
    return n;
  }

  std::atomic<bool> throw_on_state{false};
  std::vector<Frame> frames;
  std::vector<Reply> replies;
  std::vector<VecReply> vec_replies;
  std::vector<AssetWant> asset_wants;
  std::vector<Event> events;
  std::vector<Applied> applied;
  std::vector<Replica> replicas;

 private:
  mutable std::mutex m_;
  std::condition_variable cv_;
};

// The report's S1 car on a plane, dt 5e-5 (plain.json's): stable, cheap to step thousands of times.
inline std::string carScenario(double dt = 5e-5, int output_rate = 50) {
  return R"({"name": "s1", "duration": 5, "output_rate": )" + std::to_string(output_rate) +
         R"(, "physics": {"dt": )" + std::to_string(dt) +
         R"(}, "ground": {"type": "plane"}, "vehicle": {"name": "car", "initial": {"wheel_spin": 5}}})";
}

inline scenario::Scene carScene(double dt = 5e-5) {
  return scenario::buildScene(scenario::parseScenario(carScenario(dt)));
}

}  // namespace groundsim::session::test
