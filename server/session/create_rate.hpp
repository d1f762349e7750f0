// Creates per minute, per client (groundsim-server --client-creates): a
// token bucket per client id, full at `per_minute` creates and refilled at
// per_minute / 60 a second, so a client may create a burst of that many and
// then one every 60 / per_minute seconds. Client ids are whatever a request
// carries (LCM has no authentication: docs/reliability.md, Fairness), so
// this bounds a looping or buggy client, not a host that forges ids; the
// table of clients is bounded (kMaxClients), forgetting full buckets first.
// Thread-safe.
#pragma once

#include <cstddef>
#include <mutex>
#include <string>
#include <unordered_map>

#include "clock.hpp"
#include "hosted.hpp"

namespace groundsim::session {

class CreateRate {
 public:
  static constexpr std::size_t kMaxClients = 4096;
  explicit CreateRate(double per_minute) : per_minute_(per_minute) {}
  // Takes one create from the client's bucket, or says why not (code
  // TooManySessions, the limit and its flag). per_minute <= 0: no limit.
  OwnerCheck take(const std::string& client, TimePoint now);

 private:
  struct Bucket {
    double tokens = 0;
    TimePoint at{};
  };
  double refill(Bucket& b, TimePoint now) const;
  void makeRoom(TimePoint now);

  double per_minute_;
  std::mutex mutex_;
  std::unordered_map<std::string, Bucket> buckets_;
};

}  // namespace groundsim::session
