// Test data shared by mcap_test.cpp and mcap_sample.cpp: smooth JSON-like
// state text of about 300 bytes, what a recorded session writes.
#pragma once

#include <charconv>
#include <cmath>
#include <initializer_list>
#include <string>

namespace groundsim::recording::test {

inline std::string smoothJson(int g, int i) {
  const double t = i * 0.01, p = g * 0.7;
  // std::to_chars: the sample's cost is the writer's, not printf's
  std::string s;
  s.reserve(320);
  char b[32];
  auto num = [&](double v, int digits) {
    s.append(b, std::to_chars(b, b + sizeof b, v, std::chars_format::fixed, digits).ptr);
  };
  auto list = [&](const char* key, std::initializer_list<double> v, int digits) {
    s += key;
    s += '[';
    for (double x : v) {
      num(x, digits);
      s += ',';
    }
    s.back() = ']';
  };
  s += "{\"t\":";
  num(t, 2);
  s += ",\"session\":" + std::to_string(g);
  list(",\"pos\":", {40 * std::sin(0.05 * t + p), 40 * std::cos(0.05 * t + p), 0.3 + 0.01 * std::sin(t)}, 4);
  list(",\"vel\":", {2 * std::cos(0.05 * t + p), -2 * std::sin(0.05 * t + p), 0.01 * std::cos(t)}, 4);
  list(",\"quat\":", {std::cos(0.025 * t + p), 0.001 * std::sin(t), 0.002 * std::cos(t), std::sin(0.025 * t + p)}, 5);
  list(",\"wheel_omega\":", {30 + std::sin(t), 30 + std::cos(t), 31 + std::sin(t), 31 + std::cos(t)}, 3);
  list(",\"slip\":", {0.01 * std::sin(3 * t), 0.01 * std::cos(3 * t), 0.02 * std::sin(2 * t), 0.02 * std::cos(2 * t)}, 4);
  list(",\"wheel_load\":", {3500 + 200 * std::sin(t), 3500 + 200 * std::cos(t), 3400 + 150 * std::sin(t), 3400 + 150 * std::cos(t)}, 1);
  s += ",\"throttle\":";
  num(0.5 + 0.2 * std::sin(0.3 * t), 3);
  s += ",\"steer\":";
  num(0.1 * std::sin(0.2 * t + p), 4);
  s += ",\"health\":\"ok\"}";
  return s;
}

}  // namespace groundsim::recording::test
