// The error measure of docs/accuracy.md ("Accuracy on demand"): for each
// vehicle, the largest distance between its path and the reference's at the
// common sample times, relative to the distance the reference travelled,
// and its final speed's relative error; a run's error is the largest of
// these over its vehicles. Floors keep a parked car's error finite: the
// distance counts at least kMinDistance and the speed at least kMinSpeed,
// so a car at rest is measured in metres and m/s.
#pragma once

#include <string>

#include "accuracy/trajectory.hpp"

namespace groundsim::accuracy {

inline constexpr double kMinDistance = 1.0;  // m
inline constexpr double kMinSpeed = 1.0;     // m/s

struct RunError {
  double path = 0.0;   // largest over vehicles of path error / distance
  double speed = 0.0;  // largest over vehicles of |speed - speed_ref| / speed_ref
  int vehicle = -1;    // the vehicle with the largest of the two
  double value() const { return path > speed ? path : speed; }
};

// a against ref over the samples both have; infinite when either diverged.
// With `samples` below that count, the path over the first `samples` only
// (relative to the distance travelled in them) and no speed error.
RunError compareRuns(const Trajectory& a, const Trajectory& ref, size_t samples = static_cast<size_t>(-1));

// Distance travelled by vehicle v along the sampled path.
double distanceTravelled(const Trajectory& t, int v, size_t samples = static_cast<size_t>(-1));

}  // namespace groundsim::accuracy
