#include <algorithm>
#include <cmath>
#include <numbers>

#include "physics/road_car/steering.hpp"

namespace groundsim {
namespace {
constexpr double kRpm = 2.0 * std::numbers::pi / 60.0;  // rad/s per rpm

// Piecewise linear through (x, y), held at both ends. A speed that is not a
// number (a run diverging, its health check about to say so) reads the
// first value: it must not send the search past the table's end.
double table(const std::vector<double>& x, const std::vector<double>& y, double v) {
  if (x.empty()) return 0.0;
  if (!(v > x.front())) return y.front();
  if (v >= x.back()) return y.back();
  const auto it = std::upper_bound(x.begin(), x.end(), v);
  const size_t i = static_cast<size_t>(it - x.begin());
  const double f = (v - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + f * (y[i] - y[i - 1]);
}
}  // namespace

double engineTorque(const PowertrainParams& p, double omega) {
  if (p.electric) {
    const double w = std::abs(omega);
    if (w > p.motor_max_rpm * kRpm) return 0.0;
    return std::min(p.motor_torque, p.motor_power / std::max(w, 1e-6));
  }
  if (omega > p.redline_rpm * kRpm) return 0.0;
  return table(p.rpm, p.torque, omega / kRpm);
}

double gearRatio(const PowertrainParams& p, int g) {
  if (g == -1) return -p.reverse_gear * p.final_drive;
  if (g >= 1 && g <= static_cast<int>(p.gears.size())) return p.gears[static_cast<size_t>(g - 1)] * p.final_drive;
  return 0.0;
}

DriveOut driveTorque(const PowertrainParams& p, int gear, double throttle, double omega_wheels) {
  DriveOut out;
  const double ratio = gearRatio(p, gear);
  if (!p.present || ratio == 0.0) return out;
  const double w_in = ratio * omega_wheels;  // > 0 when the car moves the way the gear drives
  double torque = 0.0;
  if (p.electric) {
    out.engine_omega = w_in;
    torque = throttle * engineTorque(p, w_in);
  } else {
    const double idle = p.idle_rpm * kRpm;
    if (w_in < idle) {
      // clutch slipping: the engine runs between idle and the launch speed and
      // passes its torque; with the throttle shut the clutch opens (no creep)
      out.engine_omega = idle + throttle * std::max(0.0, p.launch_rpm * kRpm - idle);
      torque = throttle * engineTorque(p, out.engine_omega);
    } else {
      out.engine_omega = w_in;
      const double drag = p.engine_braking * w_in / (p.redline_rpm * kRpm);
      torque = throttle * engineTorque(p, w_in) - (1.0 - throttle) * drag;
      if (w_in > p.redline_rpm * kRpm) torque = -drag;  // fuel cut
    }
  }
  out.wheel_torque = torque * ratio * p.efficiency;
  return out;
}

int automaticGear(const PowertrainParams& p, double throttle, double omega_wheels) {
  const int n = static_cast<int>(p.gears.size());
  if (n <= 1) return 1;
  const double w = std::max(omega_wheels, 0.0);
  const double top = (p.electric ? p.motor_max_rpm : p.redline_rpm) * kRpm;
  // most wheel torque within the engine's range
  int best = 1;
  double best_t = -1.0;
  for (int g = 1; g <= n; ++g) {
    const double we = gearRatio(p, g) * w;
    if (we > top && g < n) continue;
    const double t = engineTorque(p, std::max(we, p.electric ? 0.0 : p.idle_rpm * kRpm)) * gearRatio(p, g);
    if (t > best_t * (1.0 + 1e-9)) {
      best_t = t;
      best = g;
    }
  }
  if (throttle >= 0.9 || p.electric) return best;
  // part throttle: highest gear that keeps the engine above this speed (it
  // rises with the throttle so a request for more pulls a lower gear)
  const double floor_w = (p.idle_rpm + 600.0 + throttle * 2500.0) * kRpm;
  for (int g = n; g > best; --g)
    if (gearRatio(p, g) * w >= floor_w) return g;
  return best;
}

}  // namespace groundsim
