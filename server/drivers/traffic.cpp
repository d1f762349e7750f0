#include "drivers/traffic.hpp"

#include <algorithm>
#include <cmath>

namespace groundsim::drivers {
namespace {
constexpr double kMergeThrottle = 0.3;
// a car in the path slower than kStoppedSpeed for kBlockedFor is passed:
// the bot holds it kPassOffset to one side at kPassThrottle until it is a
// car length behind
constexpr double kStoppedSpeed = 1.0;   // m/s
constexpr double kBlockedFor = 2.0;     // s
constexpr double kPassOffset = 3.5;     // m, centre to centre
constexpr double kPassThrottle = 0.35;
constexpr double kPassSteerGain = 0.3;  // steer per m of lateral error
constexpr double kPassSteer = 0.6;
constexpr double kRoomToPass = 5.0;     // m bumper to bumper: closer, it backs off first
}  // namespace

TrafficAware::TrafficAware(std::unique_ptr<Driver> inner, int body, std::vector<int> others, int rank,
                           TrafficRules rules)
    : inner_(std::move(inner)),
      body_(body),
      others_(std::move(others)),
      protected_(others_.size(), 0),
      rank_(rank),
      rules_(rules) {}

Pedals TrafficAware::drive(const Model& m, const State& s) {
  (void)m;
  Pedals p = inner_->drive(m, s);
  yielded_ = false;
  const double dt = last_t_ < 0.0 ? 0.0 : std::max(0.0, s.t - last_t_);
  last_t_ = s.t;
  if (ghost_) {  // passing through the others: nothing to keep off
    blocked_ = 0.0, passing_ = -1;
    return p;
  }
  const Mat3 R = bodyRot(s.y, body_).normalized().toRotationMatrix();
  const Vec3 c = bodyPos(s.y, body_), v = bodyVel(s.y, body_);
  const Vec3 fwd = R.col(0);
  const double speed = std::max(0.0, v.dot(fwd));
  // 1. the cars about it: the nearest in its path, one merging from alongside
  const Ahead ahead = look(s, R, c, fwd, speed, p);
  // 2. a car stopped in its path for kBlockedFor: go round it
  passIfBlocked(s, R, c, ahead, dt, p);
  if (passing_ >= 0) return p;
  if (ahead.merging && p.throttle > kMergeThrottle) {
    // let the car alongside and ahead in first (never to a stop: two cars
    // that each see the other ahead must not wait for each other)
    p.throttle = kMergeThrottle;
    yielded_ = true;
  }
  // 3. the gap kept behind the car ahead
  keepGap(ahead, speed, p);
  return p;
}

TrafficAware::Ahead TrafficAware::look(const State& s, const Mat3& R, const Vec3& c, const Vec3& fwd, double speed,
                                       Pedals& p) {
  Ahead a;
  for (size_t k = 0; k < others_.size(); ++k) {
    const int o = others_[k];
    const Vec3 d = R.transpose() * Vec3(bodyPos(s.y, o) - c);
    // overlapping side by side: no steering towards it
    if (rules_.steer_clear && std::abs(d.x()) < rules_.length && std::abs(d.y()) < rules_.lane) {
      const double before = p.steer;
      p.steer = d.y() > 0.0 ? std::min(p.steer, 0.0) : std::max(p.steer, 0.0);
      yielded_ = yielded_ || p.steer != before;
    }
    // a car under respawn protection has the way: ahead it is in the path
    // across the whole lane, and level with this one it goes first
    const bool has_way = protected_[k] != 0;
    const double corridor = has_way ? rules_.lane : rules_.corridor;
    // alongside and merging: ahead by more than a metre, or level and
    // before this car in the order
    bool first = d.x() > 1.0 || (d.x() > -1.0 && static_cast<int>(k) < rank_);
    bool alongside = std::abs(d.y()) > corridor && std::abs(d.y()) < rules_.lane && d.x() < rules_.length;
    if (has_way) {
      first = d.x() > -rules_.length;
      alongside = std::abs(d.y()) < rules_.lane && d.x() <= 0.0;
    }
    if (alongside && first) {
      a.merging = true;
      continue;
    }
    if (d.x() <= 0.0 || d.x() > rules_.look || std::abs(d.y()) > corridor) continue;
    const double g = d.x() - rules_.length;
    if (g < a.gap) {
      a.gap = g;
      a.index = static_cast<int>(k);
      a.their_speed = Vec3(bodyVel(s.y, o)).norm();
      a.closing = speed - Vec3(bodyVel(s.y, o)).dot(fwd);
    }
  }
  return a;
}

void TrafficAware::passIfBlocked(const State& s, const Mat3& R, const Vec3& c, const Ahead& ahead, double dt,
                                 Pedals& p) {
  if (passing_ < 0) {
    // (never a protected car: it was just put there and drives off)
    const bool stuck = ahead.index >= 0 && protected_[static_cast<size_t>(ahead.index)] == 0 &&
                       ahead.their_speed < kStoppedSpeed && ahead.gap < rules_.min_gap + 3.0;
    blocked_ = stuck ? blocked_ + dt : 0.0;
    if (blocked_ < kBlockedFor) return;
    // round it on the side where it leaves more room (its own offset from
    // this car's axis: a car a little to the right is passed on the left)
    const Vec3 d = R.transpose() * Vec3(bodyPos(s.y, others_[static_cast<size_t>(ahead.index)]) - c);
    passing_ = ahead.index;
    side_ = d.y() > 0.0 ? -1.0 : 1.0;
    blocked_ = 0.0;
    backing_ = true;
  }
  const Vec3 d = R.transpose() * Vec3(bodyPos(s.y, others_[static_cast<size_t>(passing_)]) - c);
  if (d.x() < -rules_.length || d.x() > rules_.look) {  // behind it (passed), or far: done
    passing_ = -1;
    return;
  }
  yielded_ = true;
  // 1. too close to turn out: back off straight, unless a car is right behind
  if (backing_ && d.x() - rules_.length < kRoomToPass && std::abs(d.y()) < rules_.corridor && !carBehind(s, R, c)) {
    p = Pedals{};
    p.reverse = true;
    p.throttle = kPassThrottle;
    return;
  }
  backing_ = false;
  // 2. hold it kPassOffset to the other side at a walking pace
  const double error = -side_ * kPassOffset - d.y();
  p = Pedals{};
  p.steer = std::clamp(-kPassSteerGain * error, -kPassSteer, kPassSteer);
  p.throttle = kPassThrottle;
}

bool TrafficAware::carBehind(const State& s, const Mat3& R, const Vec3& c) const {
  for (int o : others_) {
    const Vec3 d = R.transpose() * Vec3(bodyPos(s.y, o) - c);
    if (d.x() < 0.0 && d.x() > -(rules_.length + rules_.min_gap) && std::abs(d.y()) < rules_.corridor) return true;
  }
  return false;
}

void TrafficAware::keepGap(const Ahead& ahead, double speed, Pedals& p) {
  if (ahead.index < 0) return;
  const double gap = ahead.gap, closing = ahead.closing;
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
}

}  // namespace groundsim::drivers
