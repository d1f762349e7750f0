// Snapshot bytes (snapshot.hpp): a writer and a bounds-checked reader of
// little-endian fields. Every read checks the bytes left, so a truncated or
// forged snapshot is refused with its reason, never read past its end, and
// no count can make the reader allocate more than the snapshot's own size.
#include "experiments/snapshot.hpp"

#include <cstring>

#include "experiments/batch_env.hpp"

namespace groundsim::experiments {

constexpr std::size_t kMaxRangesText = 1 << 15;

std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
  return h;
}

namespace {

constexpr char kMagic[8] = {'G', 'S', 'E', 'N', 'V', 'S', 'N', 'P'};
// health_reason is a short message of the physics layer
constexpr std::uint32_t kMaxReason = 4096;

[[noreturn]] void bad(const std::string& why) { throw ExperimentError("snapshot", why); }

class Writer {
 public:
  void u8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, 8);
    u64(b);
  }
  void f32(float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    u32(b);
  }
  void count(std::size_t n) { u32(static_cast<std::uint32_t>(n)); }
  void bytes(const std::string& s) {
    count(s.size());
    out_ += s;
  }
  std::string& str() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(const std::string& s, std::size_t end) : s_(s), end_(end) {}
  std::uint8_t u8() {
    need(1, "a byte");
    return static_cast<std::uint8_t>(s_[pos_++]);
  }
  std::uint32_t u32() {
    need(4, "a 32-bit field");
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(s_[pos_++])) << (8 * i);
    return v;
  }
  std::uint64_t u64() {
    need(8, "a 64-bit field");
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(s_[pos_++])) << (8 * i);
    return v;
  }
  std::int64_t i64() { return static_cast<std::int64_t>(u64()); }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  double f64() {
    const std::uint64_t b = u64();
    double v;
    std::memcpy(&v, &b, 8);
    return v;
  }
  float f32() {
    const std::uint32_t b = u32();
    float v;
    std::memcpy(&v, &b, 4);
    return v;
  }
  bool flag(const char* what) {
    const std::uint8_t v = u8();
    if (v > 1) bad(std::string(what) + ": expected 0 or 1, got " + std::to_string(v));
    return v == 1;
  }
  // A count of elements of `size` bytes each: no more than the bytes left.
  std::size_t count(std::size_t size, const char* what) {
    const std::uint32_t n = u32();
    if (static_cast<std::uint64_t>(n) * size > end_ - pos_)
      bad(std::string(what) + ": " + std::to_string(n) + " elements, more than the " + std::to_string(end_ - pos_) +
          " bytes left (truncated or corrupted)");
    return n;
  }
  std::string bytes(std::size_t most, const char* what) {
    const std::size_t n = count(1, what);
    if (n > most) bad(std::string(what) + ": " + std::to_string(n) + " bytes, at most " + std::to_string(most));
    std::string v = s_.substr(pos_, n);
    pos_ += n;
    return v;
  }
  std::size_t pos() const { return pos_; }

 private:
  void need(std::size_t n, const char* what) {
    if (end_ - pos_ < n) bad(std::string("truncated: ") + what + " expected at byte " + std::to_string(pos_));
  }
  const std::string& s_;
  std::size_t end_;
  std::size_t pos_ = 0;
};

void writeControls(Writer& w, const CarControls& c) {
  w.f64(c.throttle);
  w.f64(c.brake);
  w.f64(c.steer);
  w.u8(c.handbrake ? 1 : 0);
  w.i32(c.gear);
  for (double t : c.wheel_torque) w.f64(t);
}

CarControls readControls(Reader& r) {
  CarControls c;
  c.throttle = r.f64();
  c.brake = r.f64();
  c.steer = r.f64();
  c.handbrake = r.flag("handbrake");
  c.gear = r.i32();
  for (double& t : c.wheel_torque) t = r.f64();
  return c;
}

void writeWheels(Writer& w, const std::vector<WheelControl>& v) {
  w.count(v.size());
  for (const WheelControl& c : v) {
    w.f64(c.drive_torque);
    w.f64(c.brake_torque);
    w.f64(c.steer);
  }
}

std::vector<WheelControl> readWheels(Reader& r, const char* what) {
  std::vector<WheelControl> v(r.count(24, what));
  for (WheelControl& c : v) {
    c.drive_torque = r.f64();
    c.brake_torque = r.f64();
    c.steer = r.f64();
  }
  return v;
}

constexpr std::size_t kControlsBytes = 3 * 8 + 1 + 4 + 4 * 8;

}  // namespace

std::string encodeSnapshot(const std::string& scenario_hash, const EnvSnapshot& s) {
  Writer w;
  w.str().append(kMagic, sizeof kMagic);
  w.u32(kSnapshotVersion);
  w.bytes(scenario_hash);
  const State& st = s.state;
  w.count(static_cast<std::size_t>(st.y.size()));
  for (Eigen::Index i = 0; i < st.y.size(); ++i) w.f64(st.y[i]);
  w.f64(st.t);
  w.i64(st.tick);
  w.f64(st.h_next);
  w.f64(st.drive_work);
  w.f64(st.initial_energy);
  writeWheels(w, st.controls);
  writeWheels(w, st.applied);
  w.count(st.car_controls.size());
  for (const CarControls& c : st.car_controls) writeControls(w, c);
  w.count(st.cars.size());
  for (const CarRuntime& c : st.cars) {
    writeControls(w, c.applied);
    w.f64(c.steer_angle);
    w.i32(c.gear);
    w.f64(c.since_shift);
  }
  w.u8(static_cast<std::uint8_t>(st.health));
  w.bytes(st.health_reason.substr(0, kMaxReason));
  w.u64(s.rng);
  w.i64(s.episode);
  w.i64(s.episode_steps);
  w.count(s.returns.size());
  for (double v : s.returns) w.f64(v);
  w.count(s.done.size());
  for (std::uint8_t v : s.done) w.u8(v);
  w.count(s.active.size());
  for (std::uint8_t v : s.active) w.u8(v);
  w.u8(s.diverged ? 1 : 0);
  w.u8(s.needs_reset ? 1 : 0);
  w.count(s.previous_action.size());
  for (float v : s.previous_action) w.f32(v);
  w.count(s.drawn.size());
  for (double v : s.drawn) w.f64(v);
  w.bytes(s.ranges);
  w.count(s.observation.size());
  for (float v : s.observation) w.f32(v);
  w.count(s.track.size());
  for (double v : s.track) w.f64(v);
  w.u64(fnv1a64(w.str().data(), w.str().size()));
  return std::move(w.str());
}

EnvSnapshot decodeSnapshot(const std::string& bytes, const std::string& scenario_hash) {
  if (bytes.size() < sizeof kMagic + 4 + 8)
    bad("truncated: " + std::to_string(bytes.size()) + " bytes, too short for a snapshot");
  if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) bad("not a groundsim environment snapshot (bad magic)");
  const std::size_t end = bytes.size() - 8;
  Reader r(bytes, end);
  for (std::size_t i = 0; i < sizeof kMagic; ++i) r.u8();
  const std::uint32_t version = r.u32();
  if (version != kSnapshotVersion)
    bad("version " + std::to_string(version) + ", this build reads version " + std::to_string(kSnapshotVersion));
  // the checksum before anything is interpreted further: a corrupted
  // snapshot is named as such, not by whichever field it broke
  std::uint64_t stored = 0;
  for (int i = 0; i < 8; ++i) stored |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[end + i])) << (8 * i);
  if (fnv1a64(bytes.data(), end) != stored) bad("checksum mismatch (corrupted or truncated)");
  const std::string hash = r.bytes(256, "scenario hash");
  if (hash != scenario_hash)
    bad("taken from another scenario (scenario hash " + hash + ", this scenario's is " + scenario_hash + ")");

  EnvSnapshot s;
  State& st = s.state;
  st.y.resize(static_cast<Eigen::Index>(r.count(8, "state vector")));
  for (Eigen::Index i = 0; i < st.y.size(); ++i) st.y[i] = r.f64();
  st.t = r.f64();
  st.tick = r.i64();
  st.h_next = r.f64();
  st.drive_work = r.f64();
  st.initial_energy = r.f64();
  st.controls = readWheels(r, "wheel controls");
  st.applied = readWheels(r, "applied wheel controls");
  st.car_controls.resize(r.count(kControlsBytes, "car controls"));
  for (CarControls& c : st.car_controls) c = readControls(r);
  st.cars.resize(r.count(kControlsBytes + 20, "car runtime"));
  for (CarRuntime& c : st.cars) {
    c.applied = readControls(r);
    c.steer_angle = r.f64();
    c.gear = r.i32();
    c.since_shift = r.f64();
  }
  const std::uint8_t health = r.u8();
  if (health > static_cast<std::uint8_t>(Health::Energy)) bad("health: unknown value " + std::to_string(health));
  st.health = static_cast<Health>(health);
  st.health_reason = r.bytes(kMaxReason, "health reason");
  s.rng = r.u64();
  s.episode = r.i64();
  s.episode_steps = r.i64();
  s.returns.resize(r.count(8, "returns"));
  for (double& v : s.returns) v = r.f64();
  s.done.resize(r.count(1, "finished flags"));
  for (std::uint8_t& v : s.done) v = r.flag("finished") ? 1 : 0;
  s.active.resize(r.count(1, "active flags"));
  for (std::uint8_t& v : s.active) v = r.flag("active") ? 1 : 0;
  s.diverged = r.flag("diverged");
  s.needs_reset = r.flag("needs_reset");
  s.previous_action.resize(r.count(4, "previous action"));
  for (float& v : s.previous_action) v = r.f32();
  s.drawn.resize(r.count(8, "drawn values"));
  for (double& v : s.drawn) v = r.f64();
  // 64 parameters of 256-character paths fit in 24 KiB
  s.ranges = r.bytes(kMaxRangesText, "randomisation ranges");
  s.observation.resize(r.count(4, "observation"));
  for (float& v : s.observation) v = r.f32();
  s.track.resize(r.count(8, "track progress"));
  for (double& v : s.track) v = r.f64();
  if (r.pos() != end) bad(std::to_string(end - r.pos()) + " unexpected bytes after the payload");
  return s;
}

}  // namespace groundsim::experiments
