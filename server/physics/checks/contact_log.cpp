#include "physics/checks/contact_log.hpp"

#include <algorithm>
#include <cmath>

#include "physics/core/state.hpp"

namespace groundsim {
namespace {

Vec3 refVelocity(const Model& m, const State& s, int group) {
  const int b = m.groups[group].ref_body;
  return b < 0 ? Vec3::Zero() : Vec3(bodyVel(s.y, b));
}

// What "hard" is measured against: the lighter vehicle of the pair (a car
// that knocks a cone over is not hit hard), else the lighter object.
double referenceMass(const Model& m, const Hit& h) {
  const CollisionGroup &a = m.groups[h.a], &b = m.groups[h.b];
  auto mass = [](const CollisionGroup& g, bool vehicles_only) {
    if (g.ref_body < 0 || (vehicles_only && g.vehicle < 0)) return 1e300;
    return g.mass;
  };
  double ref = std::min(mass(a, true), mass(b, true));
  if (ref >= 1e300) ref = std::min(mass(a, false), mass(b, false));
  return ref;
}

}  // namespace

void ContactLog::update(const Model& m, const State& s, const Workspace& ws, double dt) {
  if (active_.empty() && ws.pair_contacts.empty()) return;
  next_.clear();
  for (const PairContact& pc : ws.pair_contacts) {
    auto it = std::find_if(active_.begin(), active_.end(), [&](const Hit& h) { return h.a == pc.a && h.b == pc.b; });
    Hit h;
    if (it != active_.end()) {
      h = *it;
    } else {
      h.a = pc.a;
      h.b = pc.b;
      h.begin = s.t;
      const Vec3 n = pc.force.norm() > 0.0 ? Vec3(pc.force.normalized()) : Vec3::Zero();
      // a is pushed along n: it was approaching b along -n
      h.closing_speed = std::max(0.0, (refVelocity(m, s, pc.b) - refVelocity(m, s, pc.a)).dot(n));
    }
    h.end = s.t;
    h.momentum += pc.force * dt;
    h.force = pc.force;
    h.impulse = h.momentum.norm();
    h.peak_force = std::max(h.peak_force, pc.force.norm());
    h.depth = std::max(h.depth, pc.depth);
    if (pc.normal > 0.0) h.where = pc.where;  // a step of pure overlap (force clamped to 0) keeps the last
    h.hard = h.impulse > m.opt.collision.hard_impact_dv * referenceMass(m, h);
    next_.push_back(h);
  }
  for (const Hit& h : active_) {
    const bool still = std::any_of(next_.begin(), next_.end(), [&](const Hit& n) { return n.a == h.a && n.b == h.b; });
    if (still) continue;
    if (ended_.size() >= kMaxEnded) {
      ended_.erase(ended_.begin());
      ++dropped_;
    }
    ended_.push_back(h);
  }
  active_.swap(next_);
}

std::vector<Hit> ContactLog::takeEnded() {
  std::vector<Hit> out;
  out.swap(ended_);
  return out;
}

void ContactLog::clear() {
  active_.clear();
  ended_.clear();
  next_.clear();
}

}  // namespace groundsim
