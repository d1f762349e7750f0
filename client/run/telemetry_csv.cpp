#include "telemetry_csv.hpp"

#include <cmath>
#include <cstdio>

namespace groundsim::cli {
namespace {

constexpr const char* kWheelSuffix[4] = {"fl", "fr", "rl", "rr"};

// 9 significant digits: below the model's own accuracy, and a row of 30
// columns stays ~300 bytes at 50 frames per second
void put(std::string& out, double v) {
  out += ',';
  if (!std::isfinite(v)) return;  // never NaN in a file
  char buf[32];
  const int n = std::snprintf(buf, sizeof buf, "%.9g", v);
  out.append(buf, static_cast<size_t>(n));
}

// RFC 4180 quoting, only when needed (validated names never need it)
void putText(std::string& out, const std::string& s) {
  out += ',';
  if (s.find_first_of(",\"\r\n") == std::string::npos) {
    out += s;
    return;
  }
  out += '"';
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

}  // namespace

std::string csvHeader() {
  std::string h = "t,x,y,z,vx,vy,vz,speed,vehicle,qw,qx,qy,qz,wx,wy,wz";
  for (const char* col : {"spin", "normal", "friction", "slip"})
    for (const char* w : kWheelSuffix) h += std::string(",") + col + "_" + w;
  h += ",energy,health";
  // road-car columns (empty for other vehicles' parts they lack: 0)
  h += ",gear,engine_rpm,drive_power,yaw_rate";
  for (const char* col : {"slip_ratio", "slip_angle", "travel"})
    for (const char* w : kWheelSuffix) h += std::string(",") + col + "_" + w;
  // the live error estimate (docs/accuracy.md): empty without one
  h += ",error_estimate";
  return h;
}

std::string csvRow(const groundsim::VehicleSample& s, const std::string& vehicle_name, double error_estimate) {
  std::string row;
  row.reserve(400);
  char buf[32];
  const int n = std::snprintf(buf, sizeof buf, "%.9g", std::isfinite(s.t) ? s.t : 0.0);
  row.append(buf, static_cast<size_t>(n));
  for (int i = 0; i < 3; ++i) put(row, s.position[i]);
  for (int i = 0; i < 3; ++i) put(row, s.velocity[i]);
  put(row, s.speed);
  putText(row, vehicle_name);
  put(row, s.orientation.w());
  put(row, s.orientation.x());
  put(row, s.orientation.y());
  put(row, s.orientation.z());
  for (int i = 0; i < 3; ++i) put(row, s.angular_velocity[i]);
  // a vehicle with fewer than 4 wheels leaves the rest empty, keeping columns aligned
  auto wheels = [&](auto field) {
    for (int w = 0; w < 4; ++w) {
      if (w < s.wheel_count) put(row, field(s.wheels[w]));
      else row += ',';
    }
  };
  wheels([](const groundsim::WheelSample& w) { return w.spin; });
  wheels([](const groundsim::WheelSample& w) { return w.normal_force; });
  wheels([](const groundsim::WheelSample& w) { return w.friction_force; });
  wheels([](const groundsim::WheelSample& w) { return w.slip; });
  put(row, s.energy);
  putText(row, groundsim::healthName(s.health));
  put(row, s.gear);
  put(row, s.engine_rpm);
  put(row, s.drive_power);
  put(row, s.yaw_rate);
  wheels([](const groundsim::WheelSample& w) { return w.slip_ratio; });
  wheels([](const groundsim::WheelSample& w) { return w.slip_angle; });
  wheels([](const groundsim::WheelSample& w) { return w.travel; });
  put(row, error_estimate);
  return row;
}

}  // namespace groundsim::cli
