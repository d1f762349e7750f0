// Persistent workers for VecEnv: run(job) calls job(t) once for every
// t in [0, threads), t = 0 on the calling thread, the rest on workers that
// live as long as the pool. The caller partitions its work statically by t,
// so which thread runs which environment never depends on timing. One
// thread: no workers, the calling thread does everything.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace groundsim::experiments {

class ThreadPool {
 public:
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  // fn(ctx, t) for each t; rethrows the first exception any call threw,
  // after all have finished. Allocates nothing.
  void run(void (*fn)(void*, int), void* ctx);

 private:
  void work(int t);

  std::vector<std::thread> workers_;
  std::mutex mu_;
  std::condition_variable start_, done_;
  std::uint64_t generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
  void (*fn_)(void*, int) = nullptr;
  void* ctx_ = nullptr;
  std::exception_ptr error_;
};

}  // namespace groundsim::experiments
