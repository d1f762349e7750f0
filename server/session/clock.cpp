#include "clock.hpp"

namespace groundsim::session {
namespace {

class Steady final : public SessionClock {
 public:
  TimePoint now() const override { return Clock::now(); }
};

}  // namespace

const SessionClock& steadyClock() {
  static const Steady clock;
  return clock;
}

}  // namespace groundsim::session
