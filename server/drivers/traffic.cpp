#include "drivers/traffic.hpp"

#include <algorithm>
#include <cmath>

namespace groundsim::drivers {
namespace {
constexpr double kMergeThrottle = 0.3;
}  // namespace

TrafficAware::TrafficAware(std::unique_ptr<Driver> inner, int body, std::vector<int> others, int rank,
                           TrafficRules rules)
    : inner_(std::move(inner)), body_(body), others_(std::move(others)), rank_(rank), rules_(rules) {}

Pedals TrafficAware::drive(const Model& m, const State& s) {
  Pedals p = inner_->drive(m, s);
  yielded_ = false;
  const Mat3 R = bodyRot(s.y, body_).normalized().toRotationMatrix();
  const Vec3 c = bodyPos(s.y, body_), v = bodyVel(s.y, body_);
  const Vec3 fwd = R.col(0);
  const double speed = std::max(0.0, v.dot(fwd));
  // the nearest car in the path (its gap bumper to bumper and closing
  // speed), and whether one merges from alongside, clearly ahead
  double gap = 1e300, closing = 0.0;
  bool merging = false;
  for (size_t k = 0; k < others_.size(); ++k) {
    const int o = others_[k];
    const Vec3 d = R.transpose() * Vec3(bodyPos(s.y, o) - c);
    // overlapping side by side: no steering towards it
    if (rules_.steer_clear && std::abs(d.x()) < rules_.length && std::abs(d.y()) < rules_.lane) {
      const double before = p.steer;
      p.steer = d.y() > 0.0 ? std::min(p.steer, 0.0) : std::max(p.steer, 0.0);
      yielded_ = yielded_ || p.steer != before;
    }
    // alongside: ahead by more than a metre, or level and before this car in the order
    const bool first = d.x() > 1.0 || (d.x() > -1.0 && static_cast<int>(k) < rank_);
    if (std::abs(d.y()) > rules_.corridor && std::abs(d.y()) < rules_.lane && d.x() < rules_.length && first) {
      merging = true;
      continue;
    }
    if (d.x() <= 0.0 || d.x() > rules_.look || std::abs(d.y()) > rules_.corridor) continue;
    const double g = d.x() - rules_.length;
    if (g < gap) {
      gap = g;
      closing = speed - Vec3(bodyVel(s.y, o)).dot(fwd);
    }
  }
  if (merging && p.throttle > kMergeThrottle) {
    // let the car alongside and ahead in first (never to a stop: two cars
    // that each see the other ahead must not wait for each other)
    p.throttle = kMergeThrottle;
    yielded_ = true;
  }
  if (gap > rules_.look) return p;
  (void)m;
  // the gap it keeps at its speed, and the distance it needs to shed the closing speed
  const double keep = rules_.min_gap + rules_.headway * speed;
  const double shed = closing > 0.0 ? closing * closing / (2.0 * rules_.decel) : 0.0;
  if (gap < rules_.min_gap + shed) {
    // too close for what it closes at: brake, the harder the less room
    const double need = closing > 0.0 ? closing * closing / (2.0 * std::max(gap, 0.5)) : 0.0;
    p.brake = std::max(p.brake, std::clamp(need / rules_.decel, 0.3, 1.0));
    p.throttle = 0.0;
    yielded_ = true;
  } else if (gap < keep && closing > -0.5) {
    // inside the headway: no more throttle than the room left allows
    const double room = std::clamp((gap - rules_.min_gap) / std::max(keep - rules_.min_gap, 1e-6), 0.0, 1.0);
    if (p.throttle > room) {
      p.throttle = room;
      yielded_ = true;
    }
  }
  return p;
}

}  // namespace groundsim::drivers
