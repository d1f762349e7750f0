// The worker pool's fairness and containment, with one worker so that the
// order of slices is fully determined by the queue.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "session/scheduler.hpp"

namespace groundsim::session {
namespace {

struct Counter {
  std::mutex m;
  std::condition_variable cv;
  bool waitFor(const std::function<bool()>& done) {
    std::unique_lock<std::mutex> lk(m);
    return cv.wait_for(lk, std::chrono::seconds(60), done);
  }
  void bump(std::atomic<int>& n) {
    {
      std::lock_guard<std::mutex> lk(m);
      ++n;
    }
    cv.notify_all();
  }
};

// Asks to run again at a fixed instant (the past, for a greedy task).
class Repeating final : public Task {
 public:
  Repeating(Counter& c, std::optional<TimePoint> due) : c_(c), due_(due) {}
  std::optional<TimePoint> run(TimePoint now) override {
    c_.bump(runs);
    return due_ ? *due_ : now;
  }
  void abandon(const char*) noexcept override {}
  std::atomic<int> runs{0};

 private:
  Counter& c_;
  std::optional<TimePoint> due_;
};

TEST(Scheduler, TasksDueInThePastTakeTurnsWithOthers) {
  // a due time in the past (what an overflowed conversion produced) once
  // put a task ahead of every other, forever
  Counter c;
  auto greedy1 = std::make_shared<Repeating>(c, TimePoint{});
  auto greedy2 = std::make_shared<Repeating>(c, TimePoint{});
  auto normal = std::make_shared<Repeating>(c, std::nullopt);
  Scheduler pool(1);
  // hold the one worker until all three are queued
  std::atomic<bool> go{false};
  pool.post([&] {
    std::unique_lock<std::mutex> lk(c.m);
    c.cv.wait(lk, [&] { return go.load(); });
  });
  pool.wake(greedy1);
  pool.wake(greedy2);
  pool.wake(normal);
  {
    std::lock_guard<std::mutex> lk(c.m);
    go = true;
  }
  c.cv.notify_all();
  ASSERT_TRUE(c.waitFor([&] { return greedy1->runs >= 300; }));
  pool.stop();
  // round robin: the normal task ran about as often as each greedy one
  EXPECT_GE(normal->runs.load(), 250);
  EXPECT_GE(greedy2->runs.load(), 250);
}

class Throwing final : public Task {
 public:
  explicit Throwing(Counter& c) : c_(c) {}
  std::optional<TimePoint> run(TimePoint) override { throw std::runtime_error("boom"); }
  void abandon(const char* why) noexcept override {
    {
      std::lock_guard<std::mutex> lk(c_.m);
      reason = why;
    }
    c_.bump(abandoned);
  }
  std::atomic<int> abandoned{0};
  std::string reason;

 private:
  Counter& c_;
};

TEST(Scheduler, ATaskThatThrowsIsToldSoAndCanBeWokenAgain) {
  Counter c;
  auto t = std::make_shared<Throwing>(c);
  Scheduler pool(1);
  pool.wake(t);
  ASSERT_TRUE(c.waitFor([&] { return t->abandoned >= 1; }));
  EXPECT_EQ(t->reason, "boom");
  pool.wake(t);
  ASSERT_TRUE(c.waitFor([&] { return t->abandoned >= 2; }));
}

TEST(Scheduler, BuildJobsLeaveAWorkerForSessions) {
  // two workers, two long jobs: one job waits, a session still runs
  Counter c;
  std::atomic<int> jobs_running{0}, most{0};
  std::atomic<bool> release{false};
  Scheduler pool(2);
  for (int i = 0; i < 2; ++i)
    pool.post([&] {
      const int n = ++jobs_running;
      most = std::max(most.load(), n);
      std::unique_lock<std::mutex> lk(c.m);
      c.cv.wait(lk, [&] { return release.load(); });
      --jobs_running;
    });
  auto session = std::make_shared<Repeating>(c, std::nullopt);
  pool.wake(session);
  const bool ran = c.waitFor([&] { return session->runs >= 100; });
  {
    std::lock_guard<std::mutex> lk(c.m);
    release = true;
  }
  c.cv.notify_all();
  EXPECT_TRUE(ran) << "builds held every worker";
  pool.stop();
  EXPECT_EQ(most.load(), 1);
}

// Runs once per wake, then sleeps until woken.
class Once final : public Task {
 public:
  explicit Once(Counter& c) : c_(c) {}
  std::optional<TimePoint> run(TimePoint) override {
    c_.bump(runs);
    return std::nullopt;
  }
  void abandon(const char*) noexcept override {}
  std::atomic<int> runs{0};

 private:
  Counter& c_;
};

TEST(Scheduler, WakesReachAWorkerAsleepUntilALaterTask) {
  // The worker sleeps until the later task's due time while sessions are
  // woken. It once slept on a reference into the queue's storage, which a
  // wake's push reallocates: the worker then read freed memory when it woke
  // (an ASan report in the ASan suite, undefined behaviour elsewhere).
  Counter c;
  auto later = std::make_shared<Repeating>(c, Clock::now() + std::chrono::hours(1));
  Scheduler pool(1);
  pool.wake(later);
  ASSERT_TRUE(c.waitFor([&] { return later->runs >= 1; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // let the worker go to sleep
  std::vector<std::shared_ptr<Once>> woken;
  for (int i = 0; i < 64; ++i) woken.push_back(std::make_shared<Once>(c));
  for (const auto& t : woken) pool.wake(t);
  ASSERT_TRUE(c.waitFor([&] {
    return std::all_of(woken.begin(), woken.end(), [](const auto& t) { return t->runs >= 1; });
  }));
  pool.stop();
  EXPECT_EQ(later->runs.load(), 1) << "the later task ran before its time";
}

}  // namespace
}  // namespace groundsim::session
