// The key -> state latency trace (bench/web/latency.sh ... trace): when the
// environment variable GROUNDSIM_TRACE names a file, groundsim-server and
// groundsim-web append one line per hop of a drive command and of a state
// to it, stamped in microseconds of the steady clock (CLOCK_MONOTONIC on
// Linux), which every process on the machine shares; the benchmark puts the
// page's performance.now() on it through the bridge's "wall" stamp of each
// state. Unset, each trace point costs one branch. Not a log: the benchmark
// reads it back.
#pragma once

#include <chrono>
#include <cstdint>

namespace groundsim::net {

class LatencyTrace {
 public:
  // Whether GROUNDSIM_TRACE names a writable file (opened at the first call).
  static bool on();
  // Microseconds of a steady-clock instant (or of now).
  static std::int64_t us(std::chrono::steady_clock::time_point t);
  static std::int64_t nowUs() { return us(std::chrono::steady_clock::now()); }
  // One line, printf-style; a newline is added. Thread-safe, and lines of
  // several processes do not interleave (one append write each).
  static void line(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
};

}  // namespace groundsim::net
