#include "drivers/track_course.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "drivers/classical_driver.hpp"

namespace groundsim::drivers {

BodyView viewBody(const Model& m, const Eigen::VectorXd& y, int b) {
  BodyView v;
  v.c = bodyPos(y, b);
  v.v = bodyVel(y, b);
  v.R = bodyRot(y, b).normalized().toRotationMatrix();
  v.omega = v.R * (m.bodies[static_cast<size_t>(b)].inv_inertia * (v.R.transpose() * Vec3(bodyMom(y, b))));
  return v;
}

TrackCourse::TrackCourse(const scenario::RaceSpec& race) : line_(racingLine(race), race.circuit) {
  for (const scenario::RaceGate& g : race.gates) {
    const Vec2 c{0.5 * (g.left[0] + g.right[0]), 0.5 * (g.left[1] + g.right[1])};
    gate_s_.push_back(line_.locate(c).s);
    gate_c_.push_back(c);
  }
  // a stage ends at its last gate (in driving order, before the sort below)
  finish_ = line_.closed() || gate_s_.empty() ? line_.length() : gate_s_.back();
  // in order along the line (a circuit's start gate may sit anywhere on it)
  std::vector<size_t> order(gate_s_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return gate_s_[a] < gate_s_[b]; });
  std::vector<double> s;
  std::vector<Vec2> c;
  for (size_t i : order) s.push_back(gate_s_[i]), c.push_back(gate_c_[i]);
  gate_s_ = std::move(s);
  gate_c_ = std::move(c);
  if (!race.centerline.empty() && race.half_width > 0.0) {
    half_width_ = race.half_width;
    own_bounds_ = race.centerline.size() < 3;  // racingLine took the gates instead
    if (own_bounds_) bounds_.emplace_back(std::vector<Vec2>(race.centerline.begin(), race.centerline.end()), race.circuit);
  }
}

double TrackCourse::gained(double s0, double s1) const {
  double d = s1 - s0;
  if (line_.closed()) {
    const double L = line_.length();
    if (d > 0.5 * L) d -= L;
    else if (d < -0.5 * L) d += L;
  }
  return d;
}

Vec2 TrackCourse::nextGate(double s) const {
  if (gate_c_.empty()) return line_.pointAt(s + 10.0);
  for (size_t i = 0; i < gate_s_.size(); ++i)
    if (gate_s_[i] > s) return gate_c_[i];
  return line_.closed() ? gate_c_.front() : gate_c_.back();
}

double TrackCourse::beyondEdge(const Vec2& p, const TrackLine::Where& where) const {
  if (half_width_ <= 0.0) return -1.0;
  const double offset = own_bounds_ ? bounds_.front().locate(p).offset : where.offset;
  return std::abs(offset) - half_width_;
}

Pose2 TrackCourse::moveAlong(const Pose2& pose, double ds, double dlateral) const {
  const TrackLine::Where at = line_.locate(pose.p);
  const Vec2 t0 = line_.tangentAt(at.s);
  const double relative = pose.yaw - std::atan2(t0[1], t0[0]);
  double s = at.s + ds;
  if (!line_.closed()) s = std::clamp(s, 0.0, line_.length());
  const Vec2 q = line_.pointAt(s), t = line_.tangentAt(s);
  const double off = at.offset + dlateral;
  Pose2 out;
  out.p = {q[0] - t[1] * off, q[1] + t[0] * off};
  out.yaw = std::atan2(t[1], t[0]) + relative;
  return out;
}

namespace {
// R^T (x, y, 0) on the ground plane, as goal_body does
void bodyXY(const BodyView& car, double x, double y, double* out) {
  const Vec3 d = car.R.transpose() * Vec3(x - car.c.x(), y - car.c.y(), 0.0);
  out[0] = d.x();
  out[1] = d.y();
}
}  // namespace

void trackAhead(const TrackCourse& course, const TrackLine::Where& where, const BodyView& car,
                const std::vector<double>& ahead, double* out) {
  for (size_t k = 0; k < ahead.size(); ++k) {
    const Vec2 p = course.line().pointAt(where.s + ahead[k]);
    bodyXY(car, p[0], p[1], out + 2 * k);
  }
}

void trackPose(const TrackCourse& course, const TrackLine::Where& where, const BodyView& car, double* out) {
  const Vec2 t = course.line().tangentAt(where.s);
  const double hx = car.R(0, 0), hy = car.R(1, 0), hn = std::hypot(hx, hy);
  out[0] = where.offset;
  if (hn > 0.0) {
    out[1] = (t[0] * hy - t[1] * hx) / hn;  // sin: t x h
    out[2] = (t[0] * hx + t[1] * hy) / hn;  // cos: t . h
  } else {
    out[1] = 0.0, out[2] = 1.0;  // pointing straight up or down: no heading
  }
}

void trackCurvature(const TrackCourse& course, const TrackLine::Where& where, const std::vector<double>& ahead,
                    double* out) {
  for (size_t k = 0; k < ahead.size(); ++k) out[k] = course.line().curvatureAt(where.s + ahead[k], kCurvatureWindow);
}

void nextGate(const TrackCourse& course, const TrackLine::Where& where, const BodyView& car, double* out) {
  const Vec2 g = course.nextGate(where.s);
  bodyXY(car, g[0], g[1], out);
}

}  // namespace groundsim::drivers
