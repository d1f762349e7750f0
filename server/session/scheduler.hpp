// The worker pool that steps sessions. Each task runs in slices; after a
// slice it says when it wants to run again (or sleeps until woken). Tasks
// are ordered by due time, so a session that is due soon (real time) is
// served before one that only wants "as much as possible" (fast), and a
// woken task is queued at once. A task never runs on two workers at once.
// Fairness: a slice is bounded by wall time (the task's own deadline) and a
// task that yields is queued at the end of its slice, behind every task
// already due: due tasks take turns (round robin), whatever they ask for.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <queue>
#include <thread>
#include <vector>

#include "types.hpp"

namespace groundsim::session {

class Task {
 public:
  virtual ~Task() = default;
  // One bounded slice of work; returns when to run next, or nothing to
  // sleep until wake(). A due time before the end of the slice counts as
  // the end of the slice: a task cannot jump the queue by asking for the
  // past. Tasks should handle their own exceptions; one that escapes is
  // caught by the scheduler and handed to abandon().
  virtual std::optional<TimePoint> run(TimePoint now) = 0;
  // The task's run() threw: it must publish the failure and answer whatever
  // waits on it. The task sleeps until woken again.
  virtual void abandon(const char* why) noexcept = 0;

 private:
  friend class Scheduler;
  enum class Sched { Idle, Queued, Running };
  Sched sched_ = Sched::Idle;   // guarded by the scheduler's mutex
  std::uint64_t gen_ = 0;       // queue entries of older generations are stale
  bool rewake_ = false;         // woken while running: run again at once
};

class Scheduler {
 public:
  // max_jobs: one-shot jobs (scene builds) running at once; 0 means
  // workers - 1 (at least 1), so that builds never hold every worker and
  // running sessions keep a worker of their own.
  explicit Scheduler(int workers, int max_jobs = 0);
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Runs the task as soon as a worker is free (again, if it is running).
  void wake(const std::shared_ptr<Task>& task);
  // One-shot job, e.g. building a new session's model off the receive thread.
  void post(std::function<void()> job);
  // Lets running slices finish and joins the workers; queued work is dropped.
  void stop();

  int workers() const { return static_cast<int>(threads_.size()); }
  // Busy fraction of the pool since the previous call, in [0, 1].
  double takeLoad();

 private:
  struct Entry {
    TimePoint due;
    std::uint64_t order;
    std::uint64_t gen;
    std::shared_ptr<Task> task;
    bool operator>(const Entry& o) const { return due != o.due ? due > o.due : order > o.order; }
  };
  void workerLoop();
  void enqueue(const std::shared_ptr<Task>& task, TimePoint due);  // mutex held

  std::mutex mutex_;
  std::condition_variable cv_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue_;
  std::deque<std::function<void()>> jobs_;
  int max_jobs_ = 1;
  int jobs_running_ = 0;
  std::uint64_t order_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
  std::atomic<std::int64_t> busy_ns_{0};
  std::mutex load_mutex_;
  TimePoint load_since_;
  std::int64_t load_busy_ = 0;
};

}  // namespace groundsim::session
