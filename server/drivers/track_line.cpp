#include "drivers/track_line.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace groundsim::drivers {
namespace {

double dist(const Vec2& a, const Vec2& b) { return std::hypot(b[0] - a[0], b[1] - a[1]); }
Vec2 lerp(const Vec2& a, const Vec2& b, double u) { return {a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1])}; }

}  // namespace

TrackLine::TrackLine(const std::vector<Vec2>& points, bool closed, double spacing) : closed_(closed) {
  if (points.size() < 2) throw std::invalid_argument("centre line: at least 2 points");
  if (!(spacing > 0.0)) throw std::invalid_argument("centre line: spacing must be > 0");
  // the polyline's vertices with their arc lengths (a circuit: closed)
  std::vector<Vec2> v = points;
  if (closed_ && dist(v.front(), v.back()) > 0.0) v.push_back(v.front());
  std::vector<double> at(v.size(), 0.0);
  for (size_t i = 1; i < v.size(); ++i) at[i] = at[i - 1] + dist(v[i - 1], v[i]);
  length_ = at.back();
  if (!(length_ > 0.0)) throw std::invalid_argument("centre line: zero length");
  // resampled every ds_ (a whole number of samples over the length)
  const double wanted = std::max(spacing, length_ / kMaxSamples);
  const int n = std::clamp(static_cast<int>(std::lround(std::min(length_ / wanted, double{kMaxSamples}))), 2, kMaxSamples);
  ds_ = length_ / n;
  const int count = closed_ ? n : n + 1;
  xy_.reserve(count);
  size_t seg = 1;
  for (int k = 0; k < count; ++k) {
    const double s = std::min(k * ds_, length_);
    while (seg + 1 < v.size() && at[seg] < s) ++seg;
    const double len = at[seg] - at[seg - 1];
    xy_.push_back(lerp(v[seg - 1], v[seg], len > 0.0 ? (s - at[seg - 1]) / len : 0.0));
  }
}

double TrackLine::wrap(double s) const {
  if (!closed_) return std::clamp(s, 0.0, length_);
  const double w = std::fmod(s, length_);
  return w < 0.0 ? w + length_ : w;
}

Vec2 TrackLine::segmentPoint(int i, double u) const {
  const int n = samples();
  const int j = closed_ ? (i + 1) % n : std::min(i + 1, n - 1);
  return lerp(xy_[i], xy_[j], u);
}

Vec2 TrackLine::pointAt(double s) const {
  const double w = wrap(s) / ds_;
  int i = static_cast<int>(std::floor(w));
  const int last = closed_ ? samples() - 1 : samples() - 2;
  i = std::clamp(i, 0, last);
  return segmentPoint(i, std::clamp(w - i, 0.0, 1.0));
}

Vec2 TrackLine::tangentAt(double s) const {
  const double h = 0.5 * ds_;
  const Vec2 a = pointAt(closed_ ? s - h : std::max(s - h, 0.0));
  const Vec2 b = pointAt(closed_ ? s + h : std::min(s + h, length_));
  const double l = dist(a, b);
  return l > 0.0 ? Vec2{(b[0] - a[0]) / l, (b[1] - a[1]) / l} : Vec2{1.0, 0.0};
}

double TrackLine::curvatureAt(double s, double window) const {
  const Vec2 a = pointAt(closed_ ? s - window : std::max(s - window, 0.0));
  const Vec2 b = pointAt(s);
  const Vec2 c = pointAt(closed_ ? s + window : std::min(s + window, length_));
  const double ab = dist(a, b), bc = dist(b, c), ac = dist(a, c);
  const double cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
  const double d = ab * bc * ac;
  return d > 1e-12 ? 2.0 * cross / d : 0.0;  // 1 / circumradius, signed
}

TrackLine::Where TrackLine::locate(const Vec2& p, double near_s, double reach) const {
  const int n = samples();
  const int segments = closed_ ? n : n - 1;
  int first = 0, span = segments;
  if (near_s >= 0.0) {
    const int half = static_cast<int>(std::ceil(reach / ds_));
    first = static_cast<int>(std::floor(wrap(near_s) / ds_)) - half;
    span = std::min(segments, 2 * half + 1);
    if (!closed_) {
      first = std::clamp(first, 0, std::max(segments - span, 0));
    }
  }
  Where best;
  double best_d2 = 1e300;
  for (int k = 0; k < span; ++k) {
    int i = first + k;
    if (closed_) i = ((i % segments) + segments) % segments;
    const Vec2& a = xy_[i];
    const Vec2 b = segmentPoint(i, 1.0);
    const double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
    const double u = l2 > 0.0 ? std::clamp(((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2, 0.0, 1.0) : 0.0;
    const double qx = a[0] + u * dx, qy = a[1] + u * dy;
    const double d2 = (p[0] - qx) * (p[0] - qx) + (p[1] - qy) * (p[1] - qy);
    if (d2 < best_d2) {
      best_d2 = d2;
      best.s = (i + u) * ds_;
      const double l = std::sqrt(l2);
      best.offset = l > 0.0 ? (dx * (p[1] - qy) - dy * (p[0] - qx)) / l : 0.0;
    }
  }
  best.s = wrap(best.s);
  return best;
}

SpeedProfile::SpeedProfile(const TrackLine& line, const CarLimits& car, const std::vector<double>& mu, double window)
    : line_(&line) {
  const int n = line.samples();
  if (!mu.empty() && static_cast<int>(mu.size()) != n)
    throw std::invalid_argument("speed profile: one friction per sample of the line");
  const double ds = line.spacing();
  constexpr double g = 9.81;
  auto scale = [&](int i) { return mu.empty() ? 1.0 : std::max(mu[i], 0.05); };
  auto brake = [&](int i) { return car.brake * scale(i); };
  auto accel = [&](int i) { return std::min(car.accel, g * scale(i)); };
  v_.resize(n);
  // 1. what each bend allows
  for (int i = 0; i < n; ++i) {
    const double k = std::max(std::abs(line.curvatureAt(i * ds, window)), 1.0 / car.straight_radius);
    v_[i] = std::min(car.top, std::sqrt(car.grip * scale(i) / k));
  }
  // 2. braking into each bend (backward) and accelerating out (forward);
  //    a circuit wraps, so each pass goes round twice
  const int rounds = line.closed() ? 2 : 1;
  for (int r = 0; r < rounds; ++r)
    for (int k = n - 2 + (line.closed() ? 1 : 0); k >= 0; --k) {
      const int next = (k + 1) % n;
      v_[k] = std::min(v_[k], std::sqrt(v_[next] * v_[next] + 2.0 * brake(k) * ds));
    }
  for (int r = 0; r < rounds; ++r)
    for (int k = 1; k < n + (line.closed() ? 1 : 0); ++k) {
      const int i = k % n, prev = k - 1;
      v_[i] = std::min(v_[i], std::sqrt(v_[prev] * v_[prev] + 2.0 * accel(prev) * ds));
    }
}

double SpeedProfile::at(double s) const {
  const double w = line_->wrap(s) / line_->spacing();
  const int n = static_cast<int>(v_.size());
  const int i = std::clamp(static_cast<int>(std::floor(w)), 0, n - 1);
  const int j = line_->closed() ? (i + 1) % n : std::min(i + 1, n - 1);
  const double u = std::clamp(w - i, 0.0, 1.0);
  return v_[i] + u * (v_[j] - v_[i]);
}

double SpeedProfile::lapTime() const {
  const int n = static_cast<int>(v_.size());
  const int segments = line_->closed() ? n : n - 1;
  double t = 0.0;
  for (int k = 0; k < segments; ++k) {
    const double a = v_[k], b = v_[(k + 1) % n];
    t += 2.0 * line_->spacing() / std::max(a + b, 1e-9);  // constant acceleration between samples
  }
  return t;
}

}  // namespace groundsim::drivers
