// Prometheus' text exposition format 0.0.4, written by hand: the few lines
// groundsim-server (server/lcm/metrics.hpp) and groundsim-web
// (web/bridge/web_server.cpp) serve on GET /metrics (docs/metrics.md).
//
// By hand rather than with prometheus-cpp (Debian's prometheus-cpp-dev):
// what we expose is a dozen counters and gauges that already exist as
// atomics or in the heartbeat's snapshot, so a registry, collectors and
// histograms would buy nothing, while the library would add a new build
// dependency and, for its HTTP exposer, an embedded civetweb server (and
// libcurl for push) beside the Boost.Beast the bridge already serves HTTP
// with. The format is a handful of rules (HELP/TYPE lines, escaping, float
// spelling), all of them in metrics_text.cpp and checked by `promtool check
// metrics` in integration.MetricsServerAndBridge.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>

namespace groundsim::net {

// The Content-Type of a scrape answer.
inline constexpr const char* kMetricsContentType = "text/plain; version=0.0.4; charset=utf-8";

using MetricLabel = std::pair<std::string_view, std::string_view>;

class MetricsText {
 public:
  // Starts a family: its # HELP and # TYPE lines. `type` is "counter" or
  // "gauge"; names follow the conventions (groundsim_ prefix, base units,
  // counters end in _total).
  void family(std::string_view name, std::string_view type, std::string_view help);
  // One sample of the current family (or, with labels, one series of it).
  // Label values are escaped; label names must be valid as they are.
  void sample(std::string_view name, double value, std::initializer_list<MetricLabel> labels = {});
  void sample(std::string_view name, std::int64_t value, std::initializer_list<MetricLabel> labels = {});
  void sample(std::string_view name, std::uint64_t value, std::initializer_list<MetricLabel> labels = {});
  void sample(std::string_view name, int value, std::initializer_list<MetricLabel> labels = {}) {
    sample(name, static_cast<std::int64_t>(value), labels);
  }
  // A family of one unlabelled sample.
  template <class T>
  void single(std::string_view name, std::string_view type, std::string_view help, T value) {
    family(name, type, help);
    sample(name, value);
  }

  const std::string& text() const { return text_; }
  std::string take() { return std::move(text_); }

 private:
  void begin(std::string_view name, std::initializer_list<MetricLabel> labels);
  std::string text_;
};

// groundsim_build_info{program,version,compiler,build} 1, and
// groundsim_start_time_seconds (the process' start, Unix time).
void writeBuildInfo(MetricsText& out, std::string_view program);

// A label value or a HELP text as the format wants it (\\, \n and, in
// label values, \").
std::string escapeMetricText(std::string_view s, bool label_value);
// A sample value: integers exactly, others with 17 significant digits,
// NaN, +Inf, -Inf.
std::string metricNumber(double v);

}  // namespace groundsim::net
