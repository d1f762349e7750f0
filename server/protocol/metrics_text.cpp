#include "metrics_text.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#ifndef GROUNDSIM_VERSION
#define GROUNDSIM_VERSION "unknown"
#endif

namespace groundsim::net {
namespace {

// dynamic initialisation, before main(): close enough to the process' start
const double kStartTime =
    std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();

constexpr const char* compilerName() {
#if defined(__clang__)
  return "clang " __clang_version__;
#elif defined(__GNUC__)
  return "gcc " __VERSION__;
#else
  return "unknown";
#endif
}

constexpr const char* buildName() {
#if defined(__SANITIZE_ADDRESS__)
  return "sanitize-address";
#elif defined(__SANITIZE_THREAD__)
  return "sanitize-thread";
#elif defined(NDEBUG)
  return "release";
#else
  return "debug";
#endif
}

}  // namespace

std::string escapeMetricText(std::string_view s, bool label_value) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '\\') out += "\\\\";
    else if (c == '\n') out += "\\n";
    else if (c == '"' && label_value) out += "\\\"";
    else out += c;
  }
  return out;
}

std::string metricNumber(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  char b[32];
  if (v == std::trunc(v) && std::fabs(v) < 9.007199254740992e15) std::snprintf(b, sizeof b, "%.0f", v);
  else std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

void MetricsText::family(std::string_view name, std::string_view type, std::string_view help) {
  text_ += "# HELP ";
  text_ += name;
  text_ += ' ';
  text_ += escapeMetricText(help, false);
  text_ += "\n# TYPE ";
  text_ += name;
  text_ += ' ';
  text_ += type;
  text_ += '\n';
}

void MetricsText::begin(std::string_view name, std::initializer_list<MetricLabel> labels) {
  text_ += name;
  if (labels.size() == 0) {
    text_ += ' ';
    return;
  }
  text_ += '{';
  bool first = true;
  for (const auto& [k, v] : labels) {
    if (!first) text_ += ',';
    first = false;
    text_ += k;
    text_ += "=\"";
    text_ += escapeMetricText(v, true);
    text_ += '"';
  }
  text_ += "} ";
}

void MetricsText::sample(std::string_view name, double value, std::initializer_list<MetricLabel> labels) {
  begin(name, labels);
  text_ += metricNumber(value);
  text_ += '\n';
}

void MetricsText::sample(std::string_view name, std::int64_t value, std::initializer_list<MetricLabel> labels) {
  begin(name, labels);
  text_ += std::to_string(value);
  text_ += '\n';
}

void MetricsText::sample(std::string_view name, std::uint64_t value, std::initializer_list<MetricLabel> labels) {
  begin(name, labels);
  text_ += std::to_string(value);
  text_ += '\n';
}

void writeBuildInfo(MetricsText& out, std::string_view program) {
  out.family("groundsim_build_info", "gauge", "Always 1; the labels say which build of which program answers.");
  out.sample("groundsim_build_info", 1,
             {{"program", program}, {"version", GROUNDSIM_VERSION}, {"compiler", compilerName()}, {"build", buildName()}});
  out.single("groundsim_start_time_seconds", "gauge", "When the process started, in seconds since the Unix epoch.",
             kStartTime);
}

}  // namespace groundsim::net
