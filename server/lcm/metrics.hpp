// GET /metrics (Prometheus text format 0.0.4) and GET /health of
// groundsim-server, on a small HTTP listener of their own
// (--metrics-port, docs/metrics.md).
//
// The listener is Boost.Beast on one thread with its own io_context: it
// reads only atomics and the last heartbeat's figures
// (LcmServer::counters()) and the resend ring's counts (one short lock),
// so a scrape never waits for, nor holds up, the LCM receive thread or the
// stepping workers. Beast rather than prometheus-cpp's civetweb exposer:
// Boost (header-only, libboost-dev) is already a build dependency, for the
// bridge's HTTP, and a dozen numbers need no registry
// (protocol/metrics_text.hpp says more).
//
// Bounded, so an unfriendly client on the metrics port cannot hurt the
// server: at most `connections` at once (a new one closes the oldest, so
// idle connections cannot lock a scraper out), a request larger than
// `request_bytes` or not complete within `timeout_s` is closed, only GET
// (405 otherwise), unknown paths 404.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "lcm_server.hpp"
#include "protocol/http_answer.hpp"

namespace groundsim::net {

class MetricsListener {
 public:
  struct Limits {
    int connections = 4;
    std::size_t request_bytes = 8 * 1024;
    double timeout_s = 2.0;  // to read a whole request, and to write the answer
  };
  // The answer to GET `path` (no query); called on the listener's thread.
  using Handler = std::function<HttpAnswer(std::string_view path)>;

  // Binds and starts serving on a thread of its own. Throws
  // std::runtime_error naming the address when it cannot bind.
  MetricsListener(const std::string& address, unsigned short port, Handler handler, Limits limits);
  MetricsListener(const std::string& address, unsigned short port, Handler handler)
      : MetricsListener(address, port, std::move(handler), Limits{}) {}
  ~MetricsListener();  // stops and joins the thread
  MetricsListener(const MetricsListener&) = delete;
  MetricsListener& operator=(const MetricsListener&) = delete;

  unsigned short port() const;

  struct Impl;  // metrics.cpp

 private:
  std::unique_ptr<Impl> impl_;
};

// The server's metrics in the text format.
std::string serverMetrics(const LcmServer::Counters& c, const ResendRing::Stats& resend);
// {"status":"ok","sessions":N,"load":x}, or "stopping".
// status: "ok", "stopping", or a fleet's "fenced" / "draining" (docs/fleet.md)
std::string serverHealth(const LcmServer::Counters& c, const char* status);
// /metrics and /health of `server` (which must outlive the listener); 503
// on /health once `stopping` is set.
MetricsListener::Handler serverMetricsHandler(LcmServer& server, const std::atomic<bool>& stopping);

}  // namespace groundsim::net
