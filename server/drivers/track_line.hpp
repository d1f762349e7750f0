// A race track's centre line as a driver reads it (docs/drivers.md): the
// scenario's polyline resampled by arc length, where a car is along it, a
// point ahead, the curvature there, and the speed the car can take there.
#pragma once

#include <array>
#include <vector>

namespace groundsim::drivers {

using Vec2 = std::array<double, 2>;

class TrackLine {
 public:
  // `points`: the centre line, at least 2 distinct points; `closed`: a
  // circuit (the last point joins the first). Resampled every `spacing` m,
  // or coarser where that would pass kMaxSamples (a line across the
  // scenario's 100 km). Throws std::invalid_argument for fewer than 2
  // points or zero length.
  static constexpr int kMaxSamples = 200000;
  TrackLine(const std::vector<Vec2>& points, bool closed, double spacing = 1.0);

  bool closed() const { return closed_; }
  double length() const { return length_; }
  double spacing() const { return ds_; }
  int samples() const { return static_cast<int>(xy_.size()); }

  // Arc length s wrapped into [0, length) on a circuit, clamped on a stage.
  double wrap(double s) const;
  Vec2 pointAt(double s) const;
  // Unit tangent (the way the track runs) at s.
  Vec2 tangentAt(double s) const;
  // Signed curvature at s (1/m, + = turning left), from the circle through
  // the line at s - w, s and s + w (w = `window`): a polyline's corners
  // are spread over the window instead of being spikes.
  double curvatureAt(double s, double window) const;

  struct Where {
    double s = 0.0;        // m   along the line
    double offset = 0.0;   // m   + = left of it
  };
  // The nearest point of the line to p. With `near_s` >= 0 only the part
  // within `reach` of it is searched (a car moves little between calls),
  // otherwise the whole line.
  Where locate(const Vec2& p, double near_s = -1.0, double reach = 50.0) const;

 private:
  Vec2 segmentPoint(int i, double u) const;
  bool closed_ = true;
  double ds_ = 1.0, length_ = 0.0;
  std::vector<Vec2> xy_;     // samples every ds_ (closed: not repeating the first)
};

// The fastest speed along the line a car can hold: at most sqrt(grip / |k|)
// in a bend of curvature k (lateral acceleration grip), at most `top`, and
// reachable from the next sample by braking at `brake` and from the last
// by accelerating at `accel` (the backward and forward passes of a
// quasi-steady-state lap simulation; on a circuit both wrap around).
// grip and brake are at friction 1; `mu`, one per sample of the line (or
// empty: 1), scales them where the surface changes, and caps accel at
// mu g.
// The defaults are the classical driver's: a sedan's tyres peak near mu g;
// 9 m/s^2 leaves it a margin (10 is clean on the shipped races, 12 spins
// on the circuit).
struct CarLimits {
  double grip = 9.0;       // m/s^2  lateral acceleration in steady cornering
  double brake = 8.0;      // m/s^2
  double accel = 3.0;      // m/s^2
  double top = 60.0;       // m/s
  // the gentlest bend assumed, even on a straight: a car must keep the grip
  // to correct its line (on ice, mu 0.1: at most sqrt(0.1 grip R))
  double straight_radius = 250.0;  // m
};
class SpeedProfile {
 public:
  SpeedProfile(const TrackLine& line, const CarLimits& car, const std::vector<double>& mu = {},
               double window = 8.0);
  double at(double s) const;
  // The profile's own lap time: the sum of ds / v (a stage: start to end).
  double lapTime() const;
  const std::vector<double>& speeds() const { return v_; }

 private:
  const TrackLine* line_;
  std::vector<double> v_;
};

}  // namespace groundsim::drivers
