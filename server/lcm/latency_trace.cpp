#include "latency_trace.hpp"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>

namespace groundsim::net {
namespace {

struct Sink {
  std::FILE* file = nullptr;
  Sink() {
    const char* path = std::getenv("GROUNDSIM_TRACE");
    if (!path || !*path) return;
    file = std::fopen(path, "a");
    if (!file) {
      std::fprintf(stderr, "GROUNDSIM_TRACE: cannot open %s: tracing off\n", path);
      return;
    }
    // a line is one write(2) to a file opened for appending: whole lines
    std::setvbuf(file, nullptr, _IOLBF, 1 << 12);
  }
};

const Sink& sink() {
  static const Sink s;
  return s;
}

}  // namespace

bool LatencyTrace::on() { return sink().file != nullptr; }

std::int64_t LatencyTrace::us(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
}

void LatencyTrace::line(const char* fmt, ...) {
  std::FILE* f = sink().file;
  if (!f) return;
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  const int n = std::vsnprintf(buf, sizeof buf - 1, fmt, ap);
  va_end(ap);
  if (n < 0) return;
  std::fprintf(f, "%s\n", buf);
}

}  // namespace groundsim::net
