#include "protocol/message_json.hpp"

#include <charconv>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace groundsim::record {

void appendJsonString(std::string& out, const std::string& s) {
  out += '"';
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", c);
      out += b;
    } else {
      out += static_cast<char>(c);
    }
  }
  out += '"';
}
namespace {

Precision g_precision = Precision::Fields;
int g_digits = 17;

// The decimals of each quantity under Precision::Fields (docs/logging.md,
// Size, has this table and why): what a plot or a viewer can show, and
// finer than the model's own error; exactness is kept by the applied-command
// log and `replay --resimulate`, or by --exact. A change of any of them is a
// new table: bump kFieldsVersion, so replay compares a file at the table it
// was written with.
constexpr int kFieldsVersion = 1;
constexpr int kExactField = -1;  // these stay exact: time, inputs, the error estimate
constexpr int kLength = 3;       // m: position (a millimetre)
constexpr int kTravel = 4;       // m: suspension travel, overlap depth (0.1 mm)
constexpr int kQuaternion = 4;   // unit quaternion components (0.2 mrad; 0.4 mm at 2 m)
constexpr int kSpeed = 3;        // m/s: velocity, speed, slip, closing speed (a millimetre per second)
constexpr int kAngular = 3;      // rad/s: angular velocity, yaw rate
constexpr int kAngle = 4;        // rad: slip angle, steer angle; slip ratio (-)
constexpr int kSpin = 2;         // rad/s: wheel spin (3 mm/s at a 0.3 m rim)
constexpr int kForce = 0;        // N: normal, friction, hit force (a newton)
constexpr int kEnergy = 0;       // J (a joule); also W (drive power) and rpm
constexpr int kImpulse = 3;      // N s

constexpr double kPow10[] = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};

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
  // A number of a quantity written to `decimals` under Precision::Fields
  // (kExactField: exact whatever the precision).
  Out& num(double x, int decimals = kExactField) {
    // the server never publishes NaN or infinity; JSON has no word for them
    if (!std::isfinite(x)) {
      s_ += "null";
      return *this;
    }
    if (!exact_ && decimals != kExactField && g_precision == Precision::Fields && fixed(x, decimals)) return *this;
    // exact: the shortest text that reads back as the same double (Ryu in
    // libstdc++: several times faster than printf's %.17g, and shorter)
    char b[32];
    const bool shortest = exact_ || decimals == kExactField || g_precision != Precision::Digits;
    const auto r = shortest ? std::to_chars(b, b + sizeof b, x)
                            : std::to_chars(b, b + sizeof b, x, std::chars_format::general, g_digits);
    s_.append(b, r.ptr);
    return *this;
  }
  // x rounded to a multiple of 10^-decimals, as the integer's digits with a
  // decimal point put in, trailing zeros dropped ("12.3456", "0", "-0.5").
  // False (nothing written) past 9e15 units, where a double no longer holds
  // every integer: the caller writes it exactly.
  bool fixed(double x, int decimals) {
    const double scaled = x * kPow10[decimals];
    if (!(std::fabs(scaled) < 9e15)) return false;
    long long q = std::llround(scaled);
    if (q == 0) {
      s_ += '0';
      return true;
    }
    if (q < 0) {
      s_ += '-';
      q = -q;
    }
    char b[24];
    const auto r = std::to_chars(b, b + sizeof b, q);
    const int n = static_cast<int>(r.ptr - b);
    int end = n;  // digits kept: trailing zeros of the fraction dropped
    while (end > n - decimals && end > 0 && b[end - 1] == '0') --end;
    if (n <= decimals) {
      s_ += "0.";
      s_.append(static_cast<std::size_t>(decimals - n), '0');
      s_.append(b, b + end);
    } else {
      s_.append(b, b + n - decimals);
      if (end > n - decimals) {
        s_ += '.';
        s_.append(b + n - decimals, b + end);
      }
    }
    return true;
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
    appendJsonString(s_, v);
    return *this;
  }
  template <class T>
  Out& nums(const T* v, int n, int decimals = kExactField) {
    s_ += '[';
    for (int i = 0; i < n; ++i) {
      if (i) s_ += ',';
      num(static_cast<double>(v[i]), decimals);
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

void setPrecision(Precision p, int digits) {
  g_precision = p;
  g_digits = p == Precision::Exact ? 17 : digits < 1 ? 1 : digits > 16 ? 16 : digits;
}
Precision precision() { return g_precision; }

std::string precisionName() {
  switch (g_precision) {
    case Precision::Fields: return "fields-" + std::to_string(kFieldsVersion);
    case Precision::Exact: return "exact";
    case Precision::Digits: break;
  }
  return "digits-" + std::to_string(g_digits);
}

bool parsePrecision(const std::string& name, Precision* p, int* digits) {
  const auto number = [](const std::string& s, int* v) {
    const auto r = std::from_chars(s.data(), s.data() + s.size(), *v);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
  };
  int n = 0;
  if (name == "fields-" + std::to_string(kFieldsVersion)) {
    *p = Precision::Fields;
    *digits = 17;
  } else if (name == "exact" || name == "17") {
    *p = Precision::Exact;
    *digits = 17;
  } else if (name.rfind("digits-", 0) == 0 && number(name.substr(7), &n) && n >= 1 && n <= 16) {
    *p = Precision::Digits;
    *digits = n;
  } else if (number(name, &n) && n >= 1 && n <= 16) {  // json_digits of files from before
    *p = Precision::Digits;
    *digits = n;
  } else {
    return false;
  }
  return true;
}

void setJsonDigits(int digits) { setPrecision(digits >= 17 ? Precision::Exact : Precision::Digits, digits); }
int jsonDigits() { return g_digits; }

std::string toJson(const groundsim::state_t& m) {
  Out o(300 + 700 * m.vehicles.size());
  o.open('{');
  header(o, m.utime, m.seq, m.session_id, m.t);
  o.key("tick").integer(m.tick).key("mode").integer(m.mode).key("status").integer(m.status);
  o.key("health").integer(m.health).key("status_reason").str(m.status_reason).key("energy").num(m.energy, kEnergy);
  o.key("epoch").integer(m.epoch).key("error_estimate").num(m.error_estimate);
  o.key("vehicles").open('[');
  for (const groundsim::vehicle_state_t& v : m.vehicles) {
    const int nw = v.wheel_count < 0 ? 0 : v.wheel_count > 4 ? 4 : v.wheel_count;
    o.open('{');
    o.key("name").str(v.name).key("position").nums(v.position, 3, kLength);
    o.key("orientation").nums(v.orientation, 4, kQuaternion).key("velocity").nums(v.velocity, 3, kSpeed);
    o.key("angular_velocity").nums(v.angular_velocity, 3, kAngular);
    o.key("speed").num(v.speed, kSpeed).key("wheel_count").integer(nw);
    o.key("wheel_spin").nums(v.wheel_spin, nw, kSpin).key("normal_force").nums(v.normal_force, nw, kForce);
    o.key("friction_force").nums(v.friction_force, nw, kForce).key("slip").nums(v.slip, nw, kSpeed);
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
  o.key("epoch").integer(m.epoch).key("cars").open('[');
  for (const groundsim::road_car_state_t& c : m.cars) {
    o.open('{');
    o.key("vehicle").integer(c.vehicle).key("name").str(c.name).key("speed").num(c.speed, kSpeed);
    o.key("yaw_rate").num(c.yaw_rate, kAngular).key("gear").integer(c.gear);
    o.key("engine_rpm").num(c.engine_rpm, kEnergy).key("drive_power").num(c.drive_power, kEnergy);
    o.key("slip_ratio").nums(c.slip_ratio, 4, kAngle).key("slip_angle").nums(c.slip_angle, 4, kAngle);
    o.key("suspension_travel").nums(c.suspension_travel, 4, kTravel).key("normal_force").nums(c.normal_force, 4, kForce);
    o.key("throttle").num(c.throttle).key("brake").num(c.brake).key("steer").num(c.steer);
    o.key("steer_angle").num(c.steer_angle, kAngle).key("handbrake").boolean(c.handbrake);
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
  o.key("epoch").integer(m.epoch).key("objects").open('[');
  for (const groundsim::object_state_t& b : m.objects) {
    o.open('{');
    o.key("name").str(b.name).key("position").nums(b.position, 3, kLength);
    o.key("orientation").nums(b.orientation, 4, kQuaternion).key("velocity").nums(b.velocity, 3, kSpeed);
    o.key("angular_velocity").nums(b.angular_velocity, 3, kAngular);
    o.close('}');
  }
  o.close(']').key("hits").open('[');
  for (const groundsim::hit_t& h : m.hits) {
    o.open('{');
    o.key("a").str(h.a).key("b").str(h.b).key("position").nums(h.position, 3, kLength);
    o.key("force").nums(h.force, 3, kForce).key("impulse").num(h.impulse, kEnergy);
    o.key("peak_force").num(h.peak_force, kForce).key("closing_speed").num(h.closing_speed, kSpeed);
    o.key("depth").num(h.depth, kTravel).key("begin").num(h.begin).key("hard").boolean(h.hard);
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
  o.key("reason").str(m.reason).key("server_id").str(m.server_id).key("epoch").integer(m.epoch);
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
  o.key("publish_rate").num(m.publish_rate).key("reason").str(m.reason).key("epoch").integer(m.epoch);
  o.close('}');
  return o.take();
}

// The schemas: what each field is, in the units of the LCM types.
#define GS_VEC(n, what) "{\"type\":\"array\",\"items\":{\"type\":[\"number\",\"null\"]},\"maxItems\":" #n ",\"description\":\"" what "\"}"
#define GS_EPOCH                                                                                             \
  "\"epoch\":{\"type\":\"integer\",\"description\":\"the owner's claim on the session: 0 on a lone server, "       \
  "higher after each fleet failover (docs/protocol.md)\"},"
#define GS_HEAD                                                                                              \
  "\"utime\":{\"type\":\"integer\",\"description\":\"simulation time, microseconds\"},"                       \
  "\"seq\":{\"type\":\"integer\",\"description\":\"the session's state sequence number\"},"                   \
  "\"session_id\":{\"type\":\"string\"},\"t\":{\"type\":\"number\",\"description\":\"simulation time, s\"},"

const char* stateSchema() {
  return "{\"$schema\":\"https://json-schema.org/draft/2020-12/schema\",\"title\":\"groundsim.state\","
         "\"description\":\"A session's state (lcmtypes/state_t.lcm; numbers to the precision named by the metadata groundsim/json_precision, docs/logging.md)\",\"type\":\"object\",\"properties\":{" GS_HEAD
         "\"tick\":{\"type\":\"integer\",\"description\":\"steps taken\"},\"mode\":{\"type\":\"integer\"},"
         "\"status\":{\"type\":\"integer\",\"description\":\"1 running, 2 paused, 3 finished, 4 diverged, 5 stopped\"},"
         "\"health\":{\"type\":\"integer\"},\"status_reason\":{\"type\":\"string\"},"
         "\"energy\":{\"type\":\"number\",\"description\":\"J\"}," GS_EPOCH
         "\"error_estimate\":{\"type\":\"number\",\"description\":\"the live error estimate (docs/accuracy.md); "
         "-1 without a tolerance\"},"
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
         "\"description\":\"Road cars' drivetrain and tyres (lcmtypes/car_state_t.lcm; numbers to the precision named by the metadata groundsim/json_precision, docs/logging.md)\",\"type\":\"object\","
         "\"properties\":{" GS_HEAD GS_EPOCH
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
         "\"description\":\"Objects with mass and hits under way (lcmtypes/contact_state_t.lcm; numbers to the precision named by the metadata groundsim/json_precision, docs/logging.md)\",\"type\":\"object\","
         "\"properties\":{" GS_HEAD GS_EPOCH
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
         "\"code\":{\"type\":\"integer\"},\"channel\":{\"type\":\"string\"},\"reason\":{\"type\":\"string\"},"
         "\"server_id\":{\"type\":\"string\",\"description\":\"the server that published it (seq counts per "
         "server)\"},\"epoch\":{\"type\":\"integer\",\"description\":\"the session's epoch when session_id is set, "
         "else 0\"}}}";
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
         "5 reset, 6 pause, 7 resume, 8 step, 9 set mode, 10 stop, 11 end, 12 respawn, 13 refine\"},"
         "\"vehicle\":{\"type\":\"integer\"},\"drive_torque\":" GS_VEC(127, "N m") ",\"brake_torque\":" GS_VEC(127, "N m") ","
         "\"steer\":" GS_VEC(127, "rad, as applied") ",\"throttle\":{\"type\":\"number\"},\"brake\":{\"type\":\"number\"},"
         "\"car_steer\":{\"type\":\"number\"},\"handbrake\":{\"type\":\"boolean\"},\"gear\":{\"type\":\"integer\"},"
         "\"wheel_torque\":" GS_VEC(4, "N m") ",\"steps\":{\"type\":\"integer\",\"description\":\"step: steps asked; refine: integrator substeps per step from here on\"},\"mode\":{\"type\":\"integer\"},"
         "\"rate\":{\"type\":\"number\"},\"publish_rate\":{\"type\":\"number\"},\"reason\":{\"type\":\"string\"},"
         "\"epoch\":{\"type\":\"integer\",\"description\":\"state_t.epoch of the owner that applied it\"}}}";
}

#undef GS_CMD_HEAD
#undef GS_VEC
#undef GS_HEAD
#undef GS_EPOCH

}  // namespace groundsim::record
