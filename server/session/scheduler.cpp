#include "scheduler.hpp"

#include <algorithm>

namespace groundsim::session {

Scheduler::Scheduler(int workers, int max_jobs) : load_since_(Clock::now()) {
  workers = std::max(1, workers);
  max_jobs_ = max_jobs > 0 ? max_jobs : std::max(1, workers - 1);
  threads_.reserve(workers);
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { workerLoop(); });
}

Scheduler::~Scheduler() { stop(); }

void Scheduler::stop() {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  for (auto& t : threads_)
    if (t.joinable()) t.join();
}

void Scheduler::enqueue(const std::shared_ptr<Task>& task, TimePoint due) {
  task->sched_ = Task::Sched::Queued;
  ++task->gen_;
  queue_.push(Entry{due, order_++, task->gen_, task});
}

void Scheduler::wake(const std::shared_ptr<Task>& task) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    if (stopping_) return;
    if (task->sched_ == Task::Sched::Running) {
      task->rewake_ = true;
      return;
    }
    enqueue(task, Clock::now());
  }
  cv_.notify_one();
}

void Scheduler::post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lk(mutex_);
    if (stopping_) return;
    jobs_.push_back(std::move(job));
  }
  cv_.notify_one();
}

void Scheduler::workerLoop() {
  std::unique_lock<std::mutex> lk(mutex_);
  while (!stopping_) {
    if (!jobs_.empty() && jobs_running_ < max_jobs_) {
      auto job = std::move(jobs_.front());
      jobs_.pop_front();
      ++jobs_running_;
      lk.unlock();
      const auto t0 = Clock::now();
      try {
        job();
      } catch (...) {
        // jobs report their own failures; nothing may take a worker down
      }
      busy_ns_ += std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
      lk.lock();
      --jobs_running_;
      cv_.notify_one();  // a job waiting for this slot
      continue;
    }
    if (queue_.empty()) {
      cv_.wait(lk);
      continue;
    }
    const Entry& top = queue_.top();
    if (top.gen != top.task->gen_ || top.task->sched_ != Task::Sched::Queued) {
      queue_.pop();  // superseded by a later wake
      continue;
    }
    const TimePoint now = Clock::now();
    if (top.due > now) {
      // a copy: wait_until reads its deadline again after waking, and a
      // wake() meanwhile may reallocate the queue's storage under top
      const TimePoint due = top.due;
      cv_.wait_until(lk, due);
      continue;
    }
    std::shared_ptr<Task> task = top.task;
    queue_.pop();
    task->sched_ = Task::Sched::Running;
    task->rewake_ = false;
    lk.unlock();

    std::optional<TimePoint> next;
    try {
      next = task->run(now);
    } catch (const std::exception& e) {
      next.reset();
      task->abandon(e.what());
    } catch (...) {
      next.reset();
      task->abandon("unknown exception");
    }
    const TimePoint end = Clock::now();
    busy_ns_ += std::chrono::duration_cast<std::chrono::nanoseconds>(end - now).count();
    if (next && *next < end) next = end;  // behind every task already due

    lk.lock();
    if (task->rewake_) next = end;
    if (next && !stopping_) {
      enqueue(task, *next);
      // another worker may be sleeping until a later due time
      cv_.notify_one();
    } else {
      task->sched_ = Task::Sched::Idle;
    }
  }
}

double Scheduler::takeLoad() {
  std::lock_guard<std::mutex> lk(load_mutex_);
  const TimePoint now = Clock::now();
  const std::int64_t busy = busy_ns_.load();
  const double wall_ns = std::chrono::duration<double, std::nano>(now - load_since_).count();
  const double load = wall_ns > 0 ? (busy - load_busy_) / (wall_ns * workers()) : 0.0;
  load_since_ = now;
  load_busy_ = busy;
  return std::clamp(load, 0.0, 1.0);
}

}  // namespace groundsim::session
