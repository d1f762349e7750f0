#include "record/message_json.hpp"

#include <charconv>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace groundsim::record {
namespace {

int g_digits = 17;

class Out {
 public:
  explicit Out(std::size_t reserve) { s_.reserve(reserve); }
  Out& raw(const char* t) {
    s_ += t;
    return *this;
  }
  // ,"key":
  Out& key(const char* k) {
    if (!s_.empty() && s_.back() != '{' && s_.back() != '[') s_ += ',';
    s_ += '"';
    s_ += k;
    s_ += "\":";
    return *this;
  }
  // exact: every number as the shortest text that reads back as the same
  // double, whatever --digits says (the applied-command log, which a
  // re-simulation needs to the bit)
  Out& exact() {
    exact_ = true;
    return *this;
  }
  Out& num(double x) {
    // the server never publishes NaN or infinity; JSON has no word for them
    if (!std::isfinite(x)) {
      s_ += "null";
      return *this;
    }
    // exact: the shortest text that reads back as the same double (Ryu in
    // libstdc++: several times faster than printf's %.17g, and shorter)
    char b[32];
    const auto r = g_digits >= 17 || exact_ ? std::to_chars(b, b + sizeof b, x)
                                  : std::to_chars(b, b + sizeof b, x, std::chars_format::general, g_digits);
    s_.append(b, r.ptr);
    return *this;
  }
  Out& integer(long long v) {
    s_ += std::to_string(v);
    return *this;
  }
  Out& boolean(bool v) {
    s_ += v ? "true" : "false";
    return *this;
  }
  Out& str(const std::string& v) {
    s_ += '"';
    for (unsigned char c : v) {
      if (c == '"' || c == '\\') {
        s_ += '\\';
        s_ += static_cast<char>(c);
      } else if (c < 0x20) {
        char b[8];
        std::snprintf(b, sizeof b, "\\u%04x", c);
        s_ += b;
      } else {
        s_ += static_cast<char>(c);
      }
    }
    s_ += '"';
    return *this;
  }
  template <class T>
  Out& nums(const T* v, int n) {
    s_ += '[';
    for (int i = 0; i < n; ++i) {
      if (i) s_ += ',';
      num(static_cast<double>(v[i]));
    }
    s_ += ']';
    return *this;
  }
  Out& bools(const bool* v, int n) {
    s_ += '[';
    for (int i = 0; i < n; ++i) {
      if (i) s_ += ',';
      boolean(v[i]);
    }
    s_ += ']';
    return *this;
  }
  Out& open(char c) {
    if (!s_.empty() && s_.back() != '{' && s_.back() != '[' && s_.back() != ':') s_ += ',';
    s_ += c;
    return *this;
  }
  Out& close(char c) {
    s_ += c;
    return *this;
  }
  std::string take() { return std::move(s_); }

 private:
  std::string s_;
  bool exact_ = false;
};

void header(Out& o, long long utime, long long seq, const std::string& session, double t) {
  o.key("utime").integer(utime).key("seq").integer(seq).key("session_id").str(session).key("t").num(t);
}

}  // namespace

void setJsonDigits(int digits) { g_digits = digits < 1 ? 1 : digits > 17 ? 17 : digits; }
int jsonDigits() { return g_digits; }

std::string toJson(const groundsim::state_t& m) {
  Out o(300 + 700 * m.vehicles.size());
  o.open('{');
  header(o, m.utime, m.seq, m.session_id, m.t);
  o.key("tick").integer(m.tick).key("mode").integer(m.mode).key("status").integer(m.status);
  o.key("health").integer(m.health).key("status_reason").str(m.status_reason).key("energy").num(m.energy);
  o.key("vehicles").open('[');
  for (const groundsim::vehicle_state_t& v : m.vehicles) {
    const int nw = v.wheel_count < 0 ? 0 : v.wheel_count > 4 ? 4 : v.wheel_count;
    o.open('{');
    o.key("name").str(v.name).key("position").nums(v.position, 3).key("orientation").nums(v.orientation, 4);
    o.key("velocity").nums(v.velocity, 3).key("angular_velocity").nums(v.angular_velocity, 3);
    o.key("speed").num(v.speed).key("wheel_count").integer(nw);
    o.key("wheel_spin").nums(v.wheel_spin, nw).key("normal_force").nums(v.normal_force, nw);
    o.key("friction_force").nums(v.friction_force, nw).key("slip").nums(v.slip, nw);
    bool contact[4];
    for (int i = 0; i < 4; ++i) contact[i] = v.in_contact[i];
    o.key("in_contact").bools(contact, nw);
    o.close('}');
  }
  o.close(']').close('}');
  return o.take();
}

std::string toJson(const groundsim::car_state_t& m) {
  Out o(200 + 600 * m.cars.size());
  o.open('{');
  header(o, m.utime, m.seq, m.session_id, m.t);
  o.key("cars").open('[');
  for (const groundsim::road_car_state_t& c : m.cars) {
    o.open('{');
    o.key("vehicle").integer(c.vehicle).key("name").str(c.name).key("speed").num(c.speed);
    o.key("yaw_rate").num(c.yaw_rate).key("gear").integer(c.gear).key("engine_rpm").num(c.engine_rpm);
    o.key("drive_power").num(c.drive_power).key("slip_ratio").nums(c.slip_ratio, 4);
    o.key("slip_angle").nums(c.slip_angle, 4).key("suspension_travel").nums(c.suspension_travel, 4);
    o.key("normal_force").nums(c.normal_force, 4).key("throttle").num(c.throttle).key("brake").num(c.brake);
    o.key("steer").num(c.steer).key("steer_angle").num(c.steer_angle).key("handbrake").boolean(c.handbrake);
    o.key("gear_request").integer(c.gear_request);
    o.close('}');
  }
  o.close(']').close('}');
  return o.take();
}

std::string toJson(const groundsim::contact_state_t& m) {
  Out o(200 + 300 * (m.objects.size() + m.hits.size()));
  o.open('{');
  header(o, m.utime, m.seq, m.session_id, m.t);
  o.key("objects").open('[');
  for (const groundsim::object_state_t& b : m.objects) {
    o.open('{');
    o.key("name").str(b.name).key("position").nums(b.position, 3).key("orientation").nums(b.orientation, 4);
    o.key("velocity").nums(b.velocity, 3).key("angular_velocity").nums(b.angular_velocity, 3);
    o.close('}');
  }
  o.close(']').key("hits").open('[');
  for (const groundsim::hit_t& h : m.hits) {
    o.open('{');
    o.key("a").str(h.a).key("b").str(h.b).key("position").nums(h.position, 3).key("force").nums(h.force, 3);
    o.key("impulse").num(h.impulse).key("peak_force").num(h.peak_force).key("closing_speed").num(h.closing_speed);
    o.key("depth").num(h.depth).key("begin").num(h.begin).key("hard").boolean(h.hard);
    o.close('}');
  }
  o.close(']').close('}');
  return o.take();
}

std::string toJson(const groundsim::event_t& m) {
  Out o(300 + m.reason.size());
  o.open('{');
  o.key("utime").integer(m.utime).key("seq").integer(m.seq).key("session_id").str(m.session_id);
  o.key("client_id").str(m.client_id).key("request_id").integer(m.request_id);
  o.key("severity").integer(m.severity).key("code").integer(m.code).key("channel").str(m.channel);
  o.key("reason").str(m.reason);
  o.close('}');
  return o.take();
}

std::string toJson(const groundsim::drive_t& m, long long after_seq) {
  Out o(200 + 80 * m.drive_torque.size());
  const int n = static_cast<int>(std::min<std::size_t>(
      {m.drive_torque.size(), m.brake_torque.size(), m.steer.size(), static_cast<std::size_t>(std::max(0, int(m.nwheels)))}));
  o.open('{');
  o.key("utime").integer(m.utime).key("seq").integer(m.seq).key("client_id").str(m.client_id);
  o.key("session_id").str(m.session_id).key("after_seq").integer(after_seq).key("vehicle").integer(m.vehicle);
  o.key("drive_torque").nums(m.drive_torque.data(), n).key("brake_torque").nums(m.brake_torque.data(), n);
  o.key("steer").nums(m.steer.data(), n);
  o.close('}');
  return o.take();
}

std::string toJson(const groundsim::controls_t& m, long long after_seq) {
  Out o(300);
  o.open('{');
  o.key("utime").integer(m.utime).key("seq").integer(m.seq).key("client_id").str(m.client_id);
  o.key("session_id").str(m.session_id).key("after_seq").integer(after_seq).key("vehicle").integer(m.vehicle);
  o.key("throttle").num(m.throttle).key("brake").num(m.brake).key("steer").num(m.steer);
  o.key("handbrake").boolean(m.handbrake).key("gear").integer(m.gear);
  o.close('}');
  return o.take();
}

std::string toJson(const groundsim::applied_t& m) {
  Out o(400);
  o.exact();
  const int n = static_cast<int>(std::min<std::size_t>({m.drive_torque.size(), m.brake_torque.size(), m.steer.size(),
                                                         static_cast<std::size_t>(std::max(0, int(m.nwheels)))}));
  o.open('{');
  o.key("utime").integer(m.utime).key("session_id").str(m.session_id).key("seq").integer(m.seq);
  o.key("frame_seq").integer(m.frame_seq).key("tick").integer(m.tick).key("t").num(m.t);
  o.key("kind").integer(m.kind).key("vehicle").integer(m.vehicle);
  o.key("drive_torque").nums(m.drive_torque.data(), n).key("brake_torque").nums(m.brake_torque.data(), n);
  o.key("steer").nums(m.steer.data(), n);
  o.key("throttle").num(m.throttle).key("brake").num(m.brake).key("car_steer").num(m.car_steer);
  o.key("handbrake").boolean(m.handbrake).key("gear").integer(m.gear).key("wheel_torque").nums(m.wheel_torque, 4);
  o.key("steps").integer(m.steps).key("mode").integer(m.mode).key("rate").num(m.rate);
  o.key("publish_rate").num(m.publish_rate).key("reason").str(m.reason);
  o.close('}');
  return o.take();
}

// The schemas: what each field is, in the units of the LCM types.
#define GS_VEC(n, what) "{\"type\":\"array\",\"items\":{\"type\":[\"number\",\"null\"]},\"maxItems\":" #n ",\"description\":\"" what "\"}"
#define GS_HEAD                                                                                              \
  "\"utime\":{\"type\":\"integer\",\"description\":\"simulation time, microseconds\"},"                       \
  "\"seq\":{\"type\":\"integer\",\"description\":\"the session's state sequence number\"},"                   \
  "\"session_id\":{\"type\":\"string\"},\"t\":{\"type\":\"number\",\"description\":\"simulation time, s\"},"

const char* stateSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.state\","
         "\"description\":\"A session's state (lcmtypes/state_t.lcm)\",\"type\":\"object\",\"properties\":{" GS_HEAD
         "\"tick\":{\"type\":\"integer\",\"description\":\"steps taken\"},\"mode\":{\"type\":\"integer\"},"
         "\"status\":{\"type\":\"integer\",\"description\":\"1 running, 2 paused, 3 finished, 4 diverged, 5 stopped\"},"
         "\"health\":{\"type\":\"integer\"},\"status_reason\":{\"type\":\"string\"},"
         "\"energy\":{\"type\":\"number\",\"description\":\"J\"},"
         "\"vehicles\":{\"type\":\"array\",\"items\":{\"type\":\"object\",\"properties\":{"
         "\"name\":{\"type\":\"string\"},\"position\":" GS_VEC(3, "m, centre of mass") ","
         "\"orientation\":" GS_VEC(4, "unit quaternion body to world, w x y z") ","
         "\"velocity\":" GS_VEC(3, "m/s") ",\"angular_velocity\":" GS_VEC(3, "rad/s, world") ","
         "\"speed\":{\"type\":\"number\",\"description\":\"m/s\"},\"wheel_count\":{\"type\":\"integer\"},"
         "\"wheel_spin\":" GS_VEC(4, "rad/s") ",\"normal_force\":" GS_VEC(4, "N") ","
         "\"friction_force\":" GS_VEC(4, "N") ",\"slip\":" GS_VEC(4, "m/s") ","
         "\"in_contact\":{\"type\":\"array\",\"items\":{\"type\":\"boolean\"}}}}}}}";
}

const char* carStateSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.car_state\","
         "\"description\":\"Road cars' drivetrain and tyres (lcmtypes/car_state_t.lcm)\",\"type\":\"object\","
         "\"properties\":{" GS_HEAD
         "\"cars\":{\"type\":\"array\",\"items\":{\"type\":\"object\",\"properties\":{"
         "\"vehicle\":{\"type\":\"integer\"},\"name\":{\"type\":\"string\"},\"speed\":{\"type\":\"number\"},"
         "\"yaw_rate\":{\"type\":\"number\"},\"gear\":{\"type\":\"integer\"},\"engine_rpm\":{\"type\":\"number\"},"
         "\"drive_power\":{\"type\":\"number\"},\"slip_ratio\":" GS_VEC(4, "-") ",\"slip_angle\":" GS_VEC(4, "rad") ","
         "\"suspension_travel\":" GS_VEC(4, "m") ",\"normal_force\":" GS_VEC(4, "N") ","
         "\"throttle\":{\"type\":\"number\"},\"brake\":{\"type\":\"number\"},\"steer\":{\"type\":\"number\"},"
         "\"steer_angle\":{\"type\":\"number\"},\"handbrake\":{\"type\":\"boolean\"},"
         "\"gear_request\":{\"type\":\"integer\"}}}}}}";
}

const char* contactStateSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.contact_state\","
         "\"description\":\"Objects with mass and hits under way (lcmtypes/contact_state_t.lcm)\",\"type\":\"object\","
         "\"properties\":{" GS_HEAD
         "\"objects\":{\"type\":\"array\",\"items\":{\"type\":\"object\",\"properties\":{\"name\":{\"type\":\"string\"},"
         "\"position\":" GS_VEC(3, "m") ",\"orientation\":" GS_VEC(4, "w x y z") ",\"velocity\":" GS_VEC(3, "m/s") ","
         "\"angular_velocity\":" GS_VEC(3, "rad/s") "}}},"
         "\"hits\":{\"type\":\"array\",\"items\":{\"type\":\"object\",\"properties\":{\"a\":{\"type\":\"string\"},"
         "\"b\":{\"type\":\"string\"},\"position\":" GS_VEC(3, "m") ",\"force\":" GS_VEC(3, "N on a") ","
         "\"impulse\":{\"type\":\"number\"},\"peak_force\":{\"type\":\"number\"},\"closing_speed\":{\"type\":\"number\"},"
         "\"depth\":{\"type\":\"number\"},\"begin\":{\"type\":\"number\"},\"hard\":{\"type\":\"boolean\"}}}}}}";
}

const char* eventSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.event\","
         "\"description\":\"A server event (lcmtypes/event_t.lcm)\",\"type\":\"object\",\"properties\":{"
         "\"utime\":{\"type\":\"integer\"},\"seq\":{\"type\":\"integer\",\"description\":\"server-wide\"},"
         "\"session_id\":{\"type\":\"string\"},\"client_id\":{\"type\":\"string\"},\"request_id\":{\"type\":\"integer\"},"
         "\"severity\":{\"type\":\"integer\",\"description\":\"0 info, 1 warning, 2 error\"},"
         "\"code\":{\"type\":\"integer\"},\"channel\":{\"type\":\"string\"},\"reason\":{\"type\":\"string\"}}}";
}

#define GS_CMD_HEAD                                                                                         \
  "\"utime\":{\"type\":\"integer\",\"description\":\"sender's clock, microseconds\"},"                     \
  "\"seq\":{\"type\":\"integer\",\"description\":\"per client\"},\"client_id\":{\"type\":\"string\"},"           \
  "\"session_id\":{\"type\":\"string\"},"                                                                      \
  "\"after_seq\":{\"type\":\"integer\",\"description\":\"the session's newest state seq when heard\"},"      \
  "\"vehicle\":{\"type\":\"integer\"},"

const char* driveSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.drive\","
         "\"description\":\"Per-wheel torques and steering sent by a player (lcmtypes/drive_t.lcm; the token is not "
         "recorded)\",\"type\":\"object\",\"properties\":{" GS_CMD_HEAD
         "\"drive_torque\":" GS_VEC(4, "N m") ",\"brake_torque\":" GS_VEC(4, "N m") ",\"steer\":" GS_VEC(4, "rad") "}}";
}

const char* controlsSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.controls\","
         "\"description\":\"A road car's controls sent by a player (lcmtypes/controls_t.lcm; the token is not "
         "recorded)\",\"type\":\"object\",\"properties\":{" GS_CMD_HEAD
         "\"throttle\":{\"type\":\"number\"},\"brake\":{\"type\":\"number\"},\"steer\":{\"type\":\"number\"},"
         "\"handbrake\":{\"type\":\"boolean\"},\"gear\":{\"type\":\"integer\"}}}";
}

const char* appliedSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.applied\","
         "\"description\":\"An entry of a session's applied-command log: what changed its simulation, at the tick it "
         "took effect, with the values applied (lcmtypes/applied_t.lcm); numbers always exact\",\"type\":\"object\","
         "\"properties\":{\"utime\":{\"type\":\"integer\",\"description\":\"simulation time, microseconds\"},"
         "\"session_id\":{\"type\":\"string\"},\"seq\":{\"type\":\"integer\",\"description\":\"per session, from 0\"},"
         "\"frame_seq\":{\"type\":\"integer\",\"description\":\"state seq of the frame published next\"},"
         "\"tick\":{\"type\":\"integer\",\"description\":\"the step from tick to tick + 1 is the first to feel it\"},"
         "\"t\":{\"type\":\"number\",\"description\":\"simulation time, s\"},"
         "\"kind\":{\"type\":\"integer\",\"description\":\"1 drive, 2 controls, 3 drive timeout, 4 controls timeout, "
         "5 reset, 6 pause, 7 resume, 8 step, 9 set mode, 10 stop, 11 end\"},"
         "\"vehicle\":{\"type\":\"integer\"},\"drive_torque\":" GS_VEC(127, "N m") ",\"brake_torque\":" GS_VEC(127, "N m") ","
         "\"steer\":" GS_VEC(127, "rad, as applied") ",\"throttle\":{\"type\":\"number\"},\"brake\":{\"type\":\"number\"},"
         "\"car_steer\":{\"type\":\"number\"},\"handbrake\":{\"type\":\"boolean\"},\"gear\":{\"type\":\"integer\"},"
         "\"wheel_torque\":" GS_VEC(4, "N m") ",\"steps\":{\"type\":\"integer\"},\"mode\":{\"type\":\"integer\"},"
         "\"rate\":{\"type\":\"number\"},\"publish_rate\":{\"type\":\"number\"},\"reason\":{\"type\":\"string\"}}}";
}

#undef GS_CMD_HEAD
#undef GS_VEC
#undef GS_HEAD

}  // namespace groundsim::record
