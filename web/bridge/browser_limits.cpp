#include "protocol/text.hpp"
#include "bridge/browser_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace groundsim::web {

namespace {
const std::set<std::string> kModes{"realtime", "fast", "lockstep"};

}  // namespace

std::optional<std::string> parseModes(const std::string& list, std::set<std::string>& out) {
  out.clear();
  std::size_t from = 0;
  while (from <= list.size()) {
    const std::size_t comma = std::min(list.find(',', from), list.size());
    const std::string m = list.substr(from, comma - from);
    if (!kModes.count(m)) return "unknown mode \"" + m + "\" (realtime, fast, lockstep)";
    out.insert(m);
    from = comma + 1;
  }
  return std::nullopt;
}

std::string joinModes(const std::set<std::string>& modes) {
  std::string s;
  for (const std::string& m : modes) s += (s.empty() ? "" : ",") + m;
  return s;
}

double TokenBucket::take(Clock::time_point now) {
  if (rate_ <= 0) return 0.0;  // no limit
  if (at_ != Clock::time_point{})
    tokens_ = std::min(burst_, tokens_ + rate_ * std::chrono::duration<double>(now - at_).count());
  at_ = now;
  if (tokens_ >= 1.0) {
    tokens_ -= 1.0;
    return 0.0;
  }
  return (1.0 - tokens_) / rate_;
}

std::optional<Refusal> BrowserAllowance::create(const BrowserLimits& l, const std::string& mode, int cars,
                                                double publish_rate, int owned, TokenBucket::Clock::time_point now) {
  if (!l.modes.count(mode))
    return Refusal{"/mode", "mode " + mode + " is not offered to browsers here (" + joinModes(l.modes) +
                                "; groundsim-web --browser-modes)"};
  if (l.cars > 0 && cars > l.cars)
    return Refusal{"/vehicles", std::to_string(cars) + " cars, at most " + std::to_string(l.cars) +
                                    " in a browser's session (groundsim-web --browser-cars)"};
  if (l.publish_rate > 0 && publish_rate > l.publish_rate)
    return Refusal{"/publish_rate", net::number(publish_rate) + " Hz, at most " + net::number(l.publish_rate) +
                                        " (groundsim-web --browser-publish-rate)"};
  if (l.sessions > 0 && owned >= l.sessions)
    return Refusal{"", "this browser owns " + std::to_string(owned) + " sessions, at most " +
                           std::to_string(l.sessions) +
                           " at once (groundsim-web --browser-sessions): leave one, it ends when nobody watches it"};
  if (const double wait = creates_.take(now); wait > 0)
    return Refusal{"", "too many creates: at most " + net::number(l.creates_per_minute) +
                           " a minute (groundsim-web --browser-creates); the next in " + net::number(std::ceil(wait * 10) / 10) +
                           " s"};
  return std::nullopt;
}

double publishRateFor(const BrowserLimits& l, double asked, double scenario_rate) {
  const double want = asked > 0 ? asked : scenario_rate;
  return l.publish_rate > 0 ? std::min(want, l.publish_rate) : want;
}

}  // namespace groundsim::web
