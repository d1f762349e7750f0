// Wall-clock pacing of a session: where simulation time should be in real
// time mode, and how many state frames it may publish right now. Every
// conversion between seconds, durations and counts saturates: an extreme
// rate or step can make a session slow, never make its due time wrap into
// the past (an int64 of nanoseconds holds only 292 years, and 1e-12 as a
// real-time factor asks for 2e10 s between frames).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "types.hpp"

namespace groundsim::session {

// Longest span pacing ever computes (~31.7 years): far beyond any wait,
// far inside Clock::duration's range from any steady-clock instant.
inline constexpr double kMaxSpanSeconds = 1e9;

inline double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
// NaN becomes 0; anything beyond kMaxSpanSeconds (either sign) is cut to it.
inline Clock::duration toDuration(double s) {
  if (!(s == s)) s = 0.0;
  s = std::clamp(s, -kMaxSpanSeconds, kMaxSpanSeconds);
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}
// floor(x) as a count in [lo, hi]; NaN gives lo.
inline std::int64_t clampedCount(double x, std::int64_t lo, std::int64_t hi) {
  if (!(x >= static_cast<double>(lo))) return lo;
  if (x >= static_cast<double>(hi)) return hi;
  return std::clamp(static_cast<std::int64_t>(std::floor(x)), lo, hi);
}

// Steps between published frames: 1/(publish_rate dt) rounded, at least 1,
// at most 1e15 (a frame every 3e7 years of simulation at dt 1e-3).
inline std::int64_t stepsPerFrame(double publish_rate, double dt) {
  return clampedCount(std::round(1.0 / (publish_rate * dt)), 1, 1'000'000'000'000'000);
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
