// Wall-clock pacing of a session: where simulation time should be in real
// time mode, and how many state frames it may publish right now.
#pragma once

#include <algorithm>
#include <chrono>

#include "types.hpp"

namespace groundsim::session {

inline double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
inline Clock::duration toDuration(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

// Maps wall time to simulation time: t(now) = sim0 + rate * (now - wall0).
// Re-anchored on every mode, rate or pause change so that a change never
// makes the session jump or race to catch up.
class RealtimeAnchor {
 public:
  void reset(TimePoint wall, double sim, double rate) { wall0_ = wall; sim0_ = sim; rate_ = rate; }
  double target(TimePoint now) const { return sim0_ + rate_ * seconds(now - wall0_); }
  TimePoint wallAt(double sim) const { return wall0_ + toDuration((sim - sim0_) / rate_); }

 private:
  TimePoint wall0_{};
  double sim0_ = 0.0;
  double rate_ = 1.0;
};

// Token bucket on published frames: at most `rate` per wall second with
// bursts of `burst`. A session that runs out stops stepping until the next
// token instead of dropping frames, so fast mode slows to what subscribers
// can take (LCM drops silently when a subscriber's queue fills).
class PublishBudget {
 public:
  PublishBudget(double rate, double burst) : rate_(rate), burst_(burst), tokens_(burst) {}
  bool take(TimePoint now) {
    refill(now);
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }
  TimePoint nextToken(TimePoint now) const {
    return now + toDuration(std::max(0.0, 1.0 - tokens_) / rate_);
  }

 private:
  void refill(TimePoint now) {
    if (last_ != TimePoint{}) tokens_ = std::min(burst_, tokens_ + rate_ * seconds(now - last_));
    last_ = now;
  }
  double rate_, burst_, tokens_;
  TimePoint last_{};
};

}  // namespace groundsim::session
