#include "bridge/state_json.hpp"

#include "protocol/message_json.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace groundsim::web {
namespace {

void num(std::string& out, double x) {
  char b[32];
  // the server never sends NaN; a replayed or foreign log might
  const int n = std::isfinite(x) ? std::snprintf(b, sizeof b, "%.7g", x) : std::snprintf(b, sizeof b, "0");
  out.append(b, n);
}

template <class Get>
void array(std::string& out, int n, Get get) {
  out += '[';
  for (int i = 0; i < n; ++i) {
    if (i) out += ',';
    num(out, get(i));
  }
  out += ']';
}

}  // namespace

std::string quoted(const std::string& s) {
  std::string out;
  record::appendJsonString(out, s);
  return out;
}

std::string stateJson(const groundsim::state_t& s, double wall_s) {
  std::string out;
  out.reserve(256 + 640 * s.vehicles.size());
  out += "{\"op\":\"state\",\"session\":" + quoted(s.session_id) + ",\"seq\":" + std::to_string(s.seq) + ",\"t\":";
  num(out, s.t);
  out += ",\"tick\":" + std::to_string(s.tick) + ",\"mode\":" + std::to_string(s.mode) +
         ",\"status\":" + std::to_string(s.status) + ",\"health\":" + std::to_string(s.health) +
         ",\"reason\":" + quoted(s.status_reason) + ",\"energy\":";
  num(out, s.energy);
  char wall[40];
  out.append(wall, std::snprintf(wall, sizeof wall, ",\"wall\":%.6f", wall_s));
  // the live error estimate (docs/accuracy.md): -1 when the session has no tolerance
  out += ",\"error_estimate\":";
  num(out, s.error_estimate);
  out += ",\"vehicles\":[";
  for (std::size_t k = 0; k < s.vehicles.size(); ++k) {
    const groundsim::vehicle_state_t& v = s.vehicles[k];
    const int nw = std::max(0, std::min<int>(v.wheel_count, 4));
    if (k) out += ',';
    out += "{\"name\":" + quoted(v.name) + ",\"p\":";
    array(out, 3, [&](int i) { return v.position[i]; });
    out += ",\"q\":";
    array(out, 4, [&](int i) { return v.orientation[i]; });
    out += ",\"v\":";
    array(out, 3, [&](int i) { return v.velocity[i]; });
    out += ",\"w\":";
    array(out, 3, [&](int i) { return v.angular_velocity[i]; });
    out += ",\"speed\":";
    num(out, v.speed);
    out += ",\"spin\":";
    array(out, nw, [&](int i) { return v.wheel_spin[i]; });
    out += ",\"N\":";
    array(out, nw, [&](int i) { return v.normal_force[i]; });
    out += ",\"F\":";
    array(out, nw, [&](int i) { return v.friction_force[i]; });
    out += ",\"slip\":";
    array(out, nw, [&](int i) { return v.slip[i]; });
    out += ",\"contact\":[";
    for (int i = 0; i < nw; ++i) out += std::string(i ? "," : "") + (v.in_contact[i] ? "true" : "false");
    out += "]}";
  }
  out += "]}";
  return out;
}

std::string carStateJson(const groundsim::car_state_t& s) {
  std::string out;
  out.reserve(128 + 400 * s.cars.size());
  out += "{\"op\":\"car\",\"session\":" + quoted(s.session_id) + ",\"seq\":" + std::to_string(s.seq) + ",\"t\":";
  num(out, s.t);
  out += ",\"cars\":[";
  for (std::size_t k = 0; k < s.cars.size(); ++k) {
    const groundsim::road_car_state_t& c = s.cars[k];
    if (k) out += ',';
    out += "{\"vehicle\":" + std::to_string(c.vehicle) + ",\"gear\":" + std::to_string(c.gear) + ",\"rpm\":";
    num(out, c.engine_rpm);
    out += ",\"power\":";
    num(out, c.drive_power);
    out += ",\"yaw_rate\":";
    num(out, c.yaw_rate);
    out += ",\"throttle\":";
    num(out, c.throttle);
    out += ",\"brake\":";
    num(out, c.brake);
    out += ",\"steer\":";
    num(out, c.steer);
    out += ",\"steer_angle\":";
    num(out, c.steer_angle);
    out += std::string(",\"handbrake\":") + (c.handbrake ? "true" : "false");
    out += ",\"gear_request\":" + std::to_string(c.gear_request) + ",\"slip_ratio\":";
    array(out, 4, [&](int i) { return c.slip_ratio[i]; });
    out += ",\"slip_angle\":";
    array(out, 4, [&](int i) { return c.slip_angle[i]; });
    out += ",\"travel\":";
    array(out, 4, [&](int i) { return c.suspension_travel[i]; });
    out += '}';
  }
  return out + "]}";
}

std::string contactJson(const groundsim::contact_state_t& s) {
  std::string out;
  out.reserve(128 + 160 * s.objects.size() + 256 * s.hits.size());
  out += "{\"op\":\"contact\",\"session\":" + quoted(s.session_id) + ",\"seq\":" + std::to_string(s.seq) + ",\"t\":";
  num(out, s.t);
  out += ",\"objects\":[";
  for (std::size_t k = 0; k < s.objects.size(); ++k) {
    const groundsim::object_state_t& o = s.objects[k];
    if (k) out += ',';
    out += "{\"name\":" + quoted(o.name) + ",\"p\":";
    array(out, 3, [&](int i) { return o.position[i]; });
    out += ",\"q\":";
    array(out, 4, [&](int i) { return o.orientation[i]; });
    out += ",\"v\":";
    array(out, 3, [&](int i) { return o.velocity[i]; });
    out += ",\"w\":";
    array(out, 3, [&](int i) { return o.angular_velocity[i]; });
    out += '}';
  }
  out += "],\"hits\":[";
  for (std::size_t k = 0; k < s.hits.size(); ++k) {
    const groundsim::hit_t& h = s.hits[k];
    if (k) out += ',';
    out += "{\"a\":" + quoted(h.a) + ",\"b\":" + quoted(h.b) + ",\"p\":";
    array(out, 3, [&](int i) { return h.position[i]; });
    out += ",\"F\":";
    array(out, 3, [&](int i) { return h.force[i]; });
    const std::pair<const char*, double> fields[] = {{"impulse", h.impulse}, {"peak", h.peak_force},
                                                     {"closing", h.closing_speed}, {"depth", h.depth},
                                                     {"begin", h.begin}};
    for (const auto& [key, value] : fields) {
      out += std::string(",\"") + key + "\":";
      num(out, value);
    }
    out += std::string(",\"hard\":") + (h.hard ? "true" : "false") + '}';
  }
  return out + "]}";
}

std::string eventJson(const groundsim::event_t& e) {
  std::string out = "{\"op\":\"event\",\"session\":" + quoted(e.session_id) +
                    ",\"severity\":" + std::to_string(e.severity) + ",\"code\":" + std::to_string(e.code) +
                    ",\"reason\":" + quoted(e.reason) + ",\"t\":";
  num(out, e.utime * 1e-6);
  return out + "}";
}

}  // namespace groundsim::web
