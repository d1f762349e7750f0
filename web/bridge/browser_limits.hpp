// What one browser may make the bridge and the server do (docs/front-end.md,
// Fairness): each bound is a groundsim-web flag, with a default for
// anonymous players on a public page. The hub asks before a create; a
// refusal names the limit and its flag, as the server's own refusals do.
// One BrowserAllowance per WebSocket, owned by the hub's browser table.
#pragma once

#include <chrono>
#include <optional>
#include <set>
#include <string>

namespace groundsim::web {

struct BrowserLimits {
  int sessions = 2;                 // --browser-sessions: sessions a browser owns (created, not yet ended) at once
  int cars = 8;                     // --browser-cars: cars in a session it creates
  std::set<std::string> modes{"realtime"};  // --browser-modes: fast and lockstep only where the operator allows
  double publish_rate = 60.0;       // --browser-publish-rate: Hz of states at most (a display's rate)
  double creates_per_minute = 20.0; // --browser-creates: a burst of this many, then one every 60/n s
  double messages_per_second = 200.0;  // --browser-messages: WebSocket messages read a second; beyond, reading waits
};

// "realtime,fast" -> the set, or why not (an unknown mode).
std::optional<std::string> parseModes(const std::string& list, std::set<std::string>& out);
std::string joinModes(const std::set<std::string>& modes);

// A token bucket: `per_second` refilled, at most `burst` held.
class TokenBucket {
 public:
  using Clock = std::chrono::steady_clock;
  TokenBucket(double per_second, double burst) : rate_(per_second), burst_(burst), tokens_(burst) {}
  // Takes one; else how long until one is there (seconds > 0).
  double take(Clock::time_point now);

 private:
  double rate_, burst_, tokens_;
  Clock::time_point at_{};
};

struct Refusal {
  std::string field, reason;
};

// One browser's share of creates.
class BrowserAllowance {
 public:
  explicit BrowserAllowance(const BrowserLimits& l)
      : creates_(l.creates_per_minute / 60.0, l.creates_per_minute) {}
  // The create's mode, cars and publish rate against the limits; then, if
  // those pass, one create from its minute's budget. `owned`: sessions the
  // browser owns now (creates under way included).
  std::optional<Refusal> create(const BrowserLimits& l, const std::string& mode, int cars, double publish_rate,
                                int owned, TokenBucket::Clock::time_point now);

 private:
  TokenBucket creates_;
};

// The publish rate a browser's create asks the server for: its own, else
// the scenario's, held to the limit (a display's rate).
double publishRateFor(const BrowserLimits& l, double asked, double scenario_rate);

}  // namespace groundsim::web
