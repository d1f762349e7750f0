#include "create_rate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "pacing.hpp"

namespace groundsim::session {

double CreateRate::refill(Bucket& b, TimePoint now) const {
  b.tokens = std::min(per_minute_, b.tokens + std::max(0.0, seconds(now - b.at)) * per_minute_ / 60.0);
  b.at = now;
  return b.tokens;
}

// Full buckets say nothing a new one would not: forgotten first; then the
// oldest, so the table stays bounded whatever ids arrive.
void CreateRate::makeRoom(TimePoint now) {
  for (auto it = buckets_.begin(); it != buckets_.end();)
    it = refill(it->second, now) >= per_minute_ ? buckets_.erase(it) : std::next(it);
  while (buckets_.size() >= kMaxClients) {
    auto oldest = std::min_element(buckets_.begin(), buckets_.end(),
                                   [](const auto& a, const auto& b) { return a.second.at < b.second.at; });
    buckets_.erase(oldest);
  }
}

OwnerCheck CreateRate::take(const std::string& client, TimePoint now) {
  if (per_minute_ <= 0) return {};
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = buckets_.find(client);
  if (it == buckets_.end()) {
    if (buckets_.size() >= kMaxClients) makeRoom(now);
    it = buckets_.emplace(client, Bucket{per_minute_, now}).first;
  }
  Bucket& b = it->second;
  if (refill(b, now) < 1.0) {
    const double wait = (1.0 - b.tokens) * 60.0 / per_minute_;
    char why[256];
    std::snprintf(why, sizeof why,
                  "too many creates from client '%.64s': at most %g a minute (server --client-creates); "
                  "the next in %.1f s",
                  client.c_str(), per_minute_, wait);
    return {ErrorCode::TooManySessions, why};
  }
  b.tokens -= 1.0;
  return {};
}

}  // namespace groundsim::session
