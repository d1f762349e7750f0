// session::Output for the datagram fuzzer: keeps the replies (so the harness
// can wait for them and learn its session's id and token) and counts states
// and events. Thread-safe: workers and the caller publish at once.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "session/types.hpp"

namespace groundsim::fuzz {

class RecordingOutput final : public session::Output {
 public:
  void publishState(const session::Frame&) override {
    std::lock_guard<std::mutex> lk(mutex_);
    ++states_;
  }
  void publishEvent(const session::Event&) override {
    std::lock_guard<std::mutex> lk(mutex_);
    ++events_;
  }
  void publishReply(const session::Reply& r) override {
    {
      std::lock_guard<std::mutex> lk(mutex_);
      replies_.push_back(r);
      if (r.op == session::Op::Create) ++create_replies_;
    }
    cv_.notify_all();
  }

  std::optional<session::Reply> waitReply(const std::string& client, std::int64_t request_id, double seconds) {
    std::unique_lock<std::mutex> lk(mutex_);
    std::optional<session::Reply> found;
    cv_.wait_for(lk, std::chrono::duration<double>(seconds), [&] {
      for (const auto& r : replies_)
        if (r.client_id == client && r.request_id == request_id) {
          found = r;
          return true;
        }
      return false;
    });
    return found;
  }

  // Creates are answered from a worker once built.
  void waitCreateReplies(int n, double seconds) {
    std::unique_lock<std::mutex> lk(mutex_);
    cv_.wait_for(lk, std::chrono::duration<double>(seconds), [&] { return create_replies_ >= n; });
  }

  int replies() {
    std::lock_guard<std::mutex> lk(mutex_);
    return static_cast<int>(replies_.size());
  }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<session::Reply> replies_;
  int create_replies_ = 0;
  long states_ = 0, events_ = 0;
};

}  // namespace groundsim::fuzz
