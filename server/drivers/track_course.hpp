// A race's track as a task observes it and a trained driver senses it
// (docs/scenario.md "Tasks", docs/drivers.md): the line a driver follows,
// its gates along it, the width the race judges "off track" by; and the
// features a car reads of it. The experiments layer's sensors and the
// policy driver call the same functions, so a bot in a session sees what
// its policy saw in training, bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "drivers/track_line.hpp"
#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "scenario/race_spec.hpp"

namespace groundsim::drivers {

// An observation value as an environment publishes it (float32): a
// non-finite one as 0 (only a diverged step could hold one), clamped to
// float's range. The policy driver rounds its senses the same way.
inline float publishedFloat(double v) {
  if (!std::isfinite(v)) return 0.0f;
  constexpr double most = std::numeric_limits<float>::max();
  return static_cast<float>(std::clamp(v, -most, most));
}

// A car's body as the features read it (world frame).
struct BodyView {
  Vec3 c = Vec3::Zero();        // m    body centre
  Vec3 v = Vec3::Zero();        // m/s  its velocity
  Vec3 omega = Vec3::Zero();    // rad/s
  Mat3 R = Mat3::Identity();    // body to world (the quaternion normalised)
};
BodyView viewBody(const Model& m, const Eigen::VectorXd& y, int body);
// The features of the body alone (3 each): up_body R^T e_z, velocity_body
// R^T v, angular_velocity_body R^T omega.
inline void upBody(const BodyView& b, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = b.R(2, i);
}
inline void velocityBody(const BodyView& b, double* out) {
  const Vec3 x = b.R.transpose() * b.v;
  for (int i = 0; i < 3; ++i) out[i] = x[i];
}
inline void angularVelocityBody(const BodyView& b, double* out) {
  const Vec3 x = b.R.transpose() * b.omega;
  for (int i = 0; i < 3; ++i) out[i] = x[i];
}

// A start pose on the ground plane.
struct Pose2 {
  Vec2 p{0.0, 0.0};
  double yaw = 0.0;  // rad
};

class TrackCourse {
 public:
  // The driver's line (racingLine: the centre line, or the gates' centres),
  // the gates located on it, and the race's own centre line and half width
  // for "off track" (when the race has a track). Throws
  // std::invalid_argument when there is no line (fewer than 2 points).
  explicit TrackCourse(const scenario::RaceSpec& race);

  const TrackLine& line() const { return line_; }
  bool circuit() const { return line_.closed(); }
  // The distance a lap covers (a circuit: the line's length), or a stage's
  // start-to-finish distance along the line (to its last gate).
  double finish() const { return finish_; }
  // Signed gain along the line from s0 to s1 (a circuit: the short way round).
  double gained(double s0, double s1) const;
  // The centre of the first gate past s (a circuit wraps; a stage past its
  // last gate keeps that one).
  Vec2 nextGate(double s) const;
  // Whether the race judges this point off its track (beyond half width of
  // its centre line); false when the race gives no width.
  bool hasWidth() const { return half_width_ > 0.0; }
  double halfWidth() const { return half_width_; }
  // How far beyond the track's edge p is (m, <= 0 on the track). `where` is
  // p located on line(): reused when the race's line is the driver's.
  double beyondEdge(const Vec2& p, const TrackLine::Where& where) const;
  // A pose moved by ds along the line and dlateral to its left, keeping
  // its offset from the line and its heading relative to it (a stage
  // clamps to its ends).
  Pose2 moveAlong(const Pose2& pose, double ds, double dlateral) const;

 private:
  TrackLine line_;
  std::vector<double> gate_s_;     // gates in order of s along line_
  std::vector<Vec2> gate_c_;
  double finish_ = 0.0;
  double half_width_ = 0.0;
  bool own_bounds_ = false;        // the race's centre line is not line_: bounds_ holds it
  std::vector<TrackLine> bounds_;  // 0 or 1
};

// The window (m) over which track_curvature reads the line's bends, as the
// classical driver's speed profile does.
inline constexpr double kCurvatureWindow = 8.0;

// The track features (scenario::Feature, docs/scenario.md), each written
// from `out`: the car located at `where` on course.line().
// TrackAhead: 2 per distance, the line's point d past the car, R^T (p - c) x, y
void trackAhead(const TrackCourse& course, const TrackLine::Where& where, const BodyView& car,
                const std::vector<double>& ahead, double* out);
// TrackPose: offset (m, + left), sin and cos of the heading error (the body's
// forward axis on the ground plane against the line's tangent, + = pointing left of it)
void trackPose(const TrackCourse& course, const TrackLine::Where& where, const BodyView& car, double* out);
// TrackCurvature: 1 per distance, the line's signed curvature d past the car
void trackCurvature(const TrackCourse& course, const TrackLine::Where& where, const std::vector<double>& ahead,
                    double* out);
// NextGate: R^T (gate centre - c) x, y
void nextGate(const TrackCourse& course, const TrackLine::Where& where, const BodyView& car, double* out);

}  // namespace groundsim::drivers
