#include "convert.hpp"

#include <algorithm>
#include <cmath>

namespace groundsim::net {
namespace {
double finiteOr0(double x) { return std::isfinite(x) ? x : 0.0; }
}  // namespace

session::Request fromMessage(const groundsim::request_t& m) {
  session::Request r;
  r.op = static_cast<session::Op>(m.op);  // unknown values are refused by the service
  r.request_id = m.request_id;
  r.client_id = m.client_id;
  r.session_id = m.session_id;
  r.token = m.token;
  r.scenario_json = m.scenario_json;
  r.duration = m.duration;
  r.mode = m.mode;
  r.rate = m.rate;
  r.publish_rate = m.publish_rate;
  r.steps = m.steps;
  return r;
}

session::Drive fromMessage(const groundsim::drive_t& m) {
  session::Drive d;
  d.client_id = m.client_id;
  d.session_id = m.session_id;
  d.token = m.token;
  d.vehicle = m.vehicle;
  const int n = std::max<int>(0, m.nwheels);
  d.wheels.resize(n);
  for (int k = 0; k < n; ++k) {
    d.wheels[k].drive_torque = m.drive_torque[k];
    d.wheels[k].brake_torque = m.brake_torque[k];
    d.wheels[k].steer = m.steer[k];
  }
  d.received = session::Clock::now();
  return d;
}

session::CarDrive fromMessage(const groundsim::controls_t& m) {
  session::CarDrive d;
  d.client_id = m.client_id;
  d.session_id = m.session_id;
  d.token = m.token;
  d.vehicle = m.vehicle;
  d.controls.throttle = m.throttle;
  d.controls.brake = m.brake;
  d.controls.steer = m.steer;
  d.controls.handbrake = m.handbrake;
  d.controls.gear = m.gear;  // controls_t.GEAR_* are CarControls::k*
  d.received = session::Clock::now();
  return d;
}

session::VecRequest fromMessage(const groundsim::vec_request_t& m) {
  session::VecRequest r;
  r.op = static_cast<session::VecOp>(m.op);  // unknown values are refused by the service
  r.request_id = m.request_id;
  r.client_id = m.client_id;
  r.session_id = m.session_id;
  r.token = m.token;
  r.scenario_json = m.scenario_json;
  r.num_envs = m.num_envs;
  r.actions = m.actions;
  r.env = m.env;
  r.has_seed = m.has_seed;
  r.seed = m.seed;
  r.snapshot.assign(m.snapshot.begin(), m.snapshot.end());
  r.received = session::Clock::now();
  return r;
}


groundsim::car_state_t toCarMessage(const session::Frame& f) {
  groundsim::car_state_t m;
  m.utime = toUtime(f.t);
  m.seq = f.seq;
  m.session_id = f.session_id;
  m.t = f.t;
  m.epoch = f.epoch;
  for (const session::CarFrame& c : f.cars) {
    if (c.vehicle < 0 || c.vehicle >= static_cast<int>(f.vehicles.size())) continue;
    const VehicleSample& s = f.vehicles[c.vehicle];
    groundsim::road_car_state_t o{};
    o.vehicle = c.vehicle;
    o.name = f.names && static_cast<size_t>(c.vehicle) < f.names->size() ? (*f.names)[c.vehicle] : std::string();
    o.speed = s.speed;
    o.yaw_rate = finiteOr0(s.yaw_rate);
    o.gear = static_cast<int8_t>(c.applied.gear);
    o.engine_rpm = finiteOr0(s.engine_rpm);
    o.drive_power = finiteOr0(s.drive_power);
    for (int k = 0; k < 4; ++k) {
      o.slip_ratio[k] = finiteOr0(s.wheels[k].slip_ratio);
      o.slip_angle[k] = finiteOr0(s.wheels[k].slip_angle);
      o.suspension_travel[k] = finiteOr0(s.wheels[k].travel);
      o.normal_force[k] = s.wheels[k].normal_force;
    }
    o.throttle = finiteOr0(c.applied.applied.throttle);
    o.brake = finiteOr0(c.applied.applied.brake);
    o.steer = finiteOr0(c.commanded.steer);
    o.steer_angle = finiteOr0(c.applied.steer_angle);
    o.handbrake = c.applied.applied.handbrake;
    o.gear_request = static_cast<int8_t>(c.commanded.gear);
    m.cars.push_back(std::move(o));
  }
  m.ncars = static_cast<int32_t>(m.cars.size());
  return m;
}

groundsim::contact_state_t toContactMessage(const session::Frame& f) {
  groundsim::contact_state_t m;
  m.utime = toUtime(f.t);
  m.seq = f.seq;
  m.session_id = f.session_id;
  m.t = f.t;
  m.epoch = f.epoch;
  const Model* model = f.model.get();
  for (const session::ObjectSample& o : f.objects) {
    groundsim::object_state_t s;
    s.name = model && o.object < static_cast<int>(model->objects.size()) ? model->objects[o.object].name : "";
    for (int i = 0; i < 3; ++i) {
      s.position[i] = finiteOr0(o.position[i]);
      s.velocity[i] = finiteOr0(o.velocity[i]);
      s.angular_velocity[i] = finiteOr0(o.angular_velocity[i]);
    }
    const double q[4] = {o.orientation.w(), o.orientation.x(), o.orientation.y(), o.orientation.z()};
    for (int i = 0; i < 4; ++i) s.orientation[i] = finiteOr0(q[i]);
    m.objects.push_back(std::move(s));
  }
  m.nobjects = static_cast<int32_t>(m.objects.size());
  for (const Hit& h : f.hits) {
    groundsim::hit_t o;
    const int ng = model ? static_cast<int>(model->groups.size()) : 0;
    o.a = h.a >= 0 && h.a < ng ? model->groups[h.a].name : "";
    o.b = h.b >= 0 && h.b < ng ? model->groups[h.b].name : "";
    for (int i = 0; i < 3; ++i) {
      o.position[i] = finiteOr0(h.where[i]);
      o.force[i] = finiteOr0(h.force[i]);
    }
    o.impulse = finiteOr0(h.impulse);
    o.peak_force = finiteOr0(h.peak_force);
    o.closing_speed = finiteOr0(h.closing_speed);
    o.depth = finiteOr0(h.depth);
    o.begin = finiteOr0(h.begin);
    o.hard = h.hard;
    m.hits.push_back(std::move(o));
  }
  m.nhits = static_cast<int32_t>(m.hits.size());
  return m;
}

groundsim::applied_t toMessage(const session::Applied& a) {
  groundsim::applied_t m{};
  m.utime = toUtime(a.t);
  m.session_id = a.session_id;
  m.seq = a.seq;
  m.frame_seq = a.frame_seq;
  m.tick = a.tick;
  m.t = a.t;
  m.kind = static_cast<int8_t>(a.kind);
  m.vehicle = a.vehicle;
  m.nwheels = static_cast<int8_t>(std::min<size_t>(a.wheels.size(), 127));
  for (int k = 0; k < m.nwheels; ++k) {
    m.drive_torque.push_back(a.wheels[k].drive_torque);
    m.brake_torque.push_back(a.wheels[k].brake_torque);
    m.steer.push_back(a.wheels[k].steer);
  }
  m.throttle = a.controls.throttle;
  m.brake = a.controls.brake;
  m.car_steer = a.controls.steer;
  m.handbrake = a.controls.handbrake;
  m.gear = static_cast<int8_t>(a.controls.gear);
  for (int k = 0; k < 4; ++k) m.wheel_torque[k] = a.controls.wheel_torque[k];
  m.steps = a.steps;
  m.mode = static_cast<int8_t>(a.mode);
  m.rate = a.rate;
  m.publish_rate = a.publish_rate;
  m.reason = a.reason;
  m.epoch = a.epoch;
  return m;
}

groundsim::state_t toMessage(const session::Frame& f) {
  groundsim::state_t m;
  m.utime = toUtime(f.t);
  m.seq = f.seq;
  m.session_id = f.session_id;
  m.t = f.t;
  m.tick = f.tick;
  m.mode = static_cast<int8_t>(f.mode);
  m.status = static_cast<int8_t>(f.status);
  m.health = static_cast<int8_t>(f.health);
  m.status_reason = f.reason;
  m.energy = f.energy;
  m.epoch = f.epoch;
  m.error_estimate = std::isfinite(f.error_estimate) ? f.error_estimate : -1.0;
  m.nvehicles = static_cast<int32_t>(f.vehicles.size());
  m.vehicles.resize(f.vehicles.size());
  for (size_t v = 0; v < f.vehicles.size(); ++v) {
    const VehicleSample& s = f.vehicles[v];
    groundsim::vehicle_state_t& o = m.vehicles[v];
    o.utime = m.utime;
    o.name = f.names && v < f.names->size() ? (*f.names)[v] : std::string();
    for (int i = 0; i < 3; ++i) {
      o.position[i] = s.position[i];
      o.velocity[i] = s.velocity[i];
      o.angular_velocity[i] = s.angular_velocity[i];
    }
    o.orientation[0] = s.orientation.w();
    o.orientation[1] = s.orientation.x();
    o.orientation[2] = s.orientation.y();
    o.orientation[3] = s.orientation.z();
    o.speed = s.speed;
    o.wheel_count = static_cast<int8_t>(s.wheel_count);
    for (int k = 0; k < 4; ++k) {
      o.wheel_spin[k] = s.wheels[k].spin;
      o.normal_force[k] = s.wheels[k].normal_force;
      o.friction_force[k] = s.wheels[k].friction_force;
      o.slip[k] = s.wheels[k].slip;
      o.in_contact[k] = s.wheels[k].in_contact;
    }
  }
  return m;
}

groundsim::env_layout_t toMessage(const experiments::Layout& l) {
  groundsim::env_layout_t m;
  m.num_envs = l.num_envs;
  m.dt = l.dt;
  m.control_period = l.control_period;
  m.time_limit = l.time_limit;
  m.obs_size = l.obsSize();
  m.observation = l.observation;
  m.observation_low = l.observation_low;
  m.observation_high = l.observation_high;
  m.observation_low.resize(l.observation.size(), -INFINITY);
  m.observation_high.resize(l.observation.size(), INFINITY);
  m.action_size = l.actionSize();
  m.action = l.action;
  m.action_low = l.action_low;
  m.action_high = l.action_high;
  m.action_low.resize(l.action.size(), -INFINITY);
  m.action_high.resize(l.action.size(), INFINITY);
  m.nvehicles = static_cast<int32_t>(l.wheel_counts.size());
  m.wheel_counts.assign(l.wheel_counts.begin(), l.wheel_counts.end());
  m.scenario_hash = l.scenario_hash;
  m.ndrawn = static_cast<int32_t>(l.drawn.size());
  m.num_agents = l.num_agents;
  m.agents = l.agents;
  m.agents.resize(static_cast<std::size_t>(std::max(0, l.num_agents)));  // lcm: the array has num_agents entries
  m.drawn = l.drawn;
  return m;
}

groundsim::vec_reply_t toMessage(const session::VecReply& r, std::int64_t seq) {
  groundsim::vec_reply_t m;
  m.utime = 0;
  m.seq = seq;
  m.request_id = r.request_id;
  m.client_id = r.client_id;
  m.session_id = r.session_id;
  m.op = static_cast<int8_t>(r.op);
  m.ok = r.ok;
  m.error_code = static_cast<int32_t>(r.code);
  m.field = r.field;
  m.error = r.error;
  m.token = r.token;
  m.part = 0;
  m.nparts = 1;
  m.tick = r.tick;
  for (const auto& s : r.sessions) m.sessions.push_back(toMessage(s, true));
  m.nsessions = static_cast<int32_t>(m.sessions.size());
  m.num_envs = r.num_envs;
  m.env_begin = r.env_begin;
  m.env_count = r.env_count;
  m.obs_size = r.obs_size;
  m.obs = r.obs;
  // never NaN on the wire (the environments sanitize; this is the last guard)
  for (float& x : m.obs)
    if (!std::isfinite(x)) x = 0.0f;
  m.nobs = static_cast<int32_t>(m.obs.size());
  m.rewards = r.rewards;
  for (double& x : m.rewards) x = finiteOr0(x);
  m.terminated.assign(r.terminated.begin(), r.terminated.end());
  m.truncated.assign(r.truncated.begin(), r.truncated.end());
  for (const experiments::EnvInfo& i : r.infos) {
    m.episode.push_back(i.episode);
    m.episode_steps.push_back(i.episode_steps);
    m.episode_return.push_back(finiteOr0(i.episode_return));
    m.diverged.push_back(i.diverged ? 1 : 0);
    m.active.push_back(i.active ? 1 : 0);
  }
  m.snapshot_total = static_cast<int32_t>(r.snapshot.size());
  m.snapshot_offset = 0;
  m.nsnapshot = m.snapshot_total;
  m.snapshot.assign(r.snapshot.begin(), r.snapshot.end());
  return m;
}

groundsim::session_info_t toMessage(const session::SessionInfo& s, bool with_layout) {
  groundsim::session_info_t m;
  m.utime = toUtime(s.t);
  m.seq = s.seq;
  m.session_id = s.session_id;
  m.name = s.name;
  m.mode = static_cast<int8_t>(s.mode);
  m.status = static_cast<int8_t>(s.status);
  m.status_reason = s.reason;
  m.rate = s.rate;
  m.publish_rate = s.publish_rate;
  m.tick = s.tick;
  m.nvehicles = static_cast<int32_t>(s.vehicle_names.size());
  m.vehicle_names = s.vehicle_names;
  m.idle_s = s.idle_s;
  m.dt = s.dt;
  m.wheel_counts.resize(s.vehicle_names.size(), 0);
  for (size_t v = 0; v < s.wheel_counts.size() && v < m.wheel_counts.size(); ++v)
    m.wheel_counts[v] = static_cast<int8_t>(std::clamp(s.wheel_counts[v], 0, 127));
  m.control_period = s.control_period;
  m.num_envs = s.num_envs;
  if (with_layout && s.layout) m.layout.push_back(toMessage(*s.layout));
  m.nlayout = static_cast<int32_t>(m.layout.size());
  m.server_id = s.server_id;
  m.epoch = s.epoch;
  return m;
}

groundsim::reply_t toMessage(const session::Reply& r, std::int64_t seq) {
  groundsim::reply_t m;
  m.utime = toUtime(r.t);
  m.seq = seq;
  m.request_id = r.request_id;
  m.client_id = r.client_id;
  m.session_id = r.session_id;
  m.op = static_cast<int8_t>(r.op);
  m.ok = r.ok;
  m.error_code = static_cast<int32_t>(r.code);
  m.error = r.error;
  m.token = r.token;
  m.nsessions = static_cast<int32_t>(r.sessions.size());
  for (const auto& s : r.sessions) m.sessions.push_back(toMessage(s));
  m.nstates = r.state ? 1 : 0;
  if (r.state) m.states.push_back(toMessage(*r.state));
  return m;
}

groundsim::event_t toMessage(const session::Event& e, std::int64_t seq) {
  groundsim::event_t m;
  m.utime = toUtime(e.t);
  m.seq = seq;
  m.session_id = e.session_id;
  m.client_id = e.client_id;
  m.request_id = e.request_id;
  m.severity = static_cast<int8_t>(e.severity);
  m.code = static_cast<int32_t>(e.code);
  m.channel = e.channel;
  m.reason = e.reason;
  m.epoch = e.epoch;
  return m;
}

session::Applied fromMessage(const groundsim::applied_t& m) {
  session::Applied a;
  a.session_id = m.session_id;
  a.seq = m.seq;
  a.frame_seq = m.frame_seq;
  a.tick = m.tick;
  a.t = m.t;
  a.kind = static_cast<session::AppliedKind>(m.kind);
  a.vehicle = m.vehicle;
  const size_t n = std::min({static_cast<size_t>(std::max<int>(m.nwheels, 0)), m.drive_torque.size(),
                             m.brake_torque.size(), m.steer.size()});
  for (size_t k = 0; k < n; ++k) a.wheels.push_back(WheelControl{m.drive_torque[k], m.brake_torque[k], m.steer[k]});
  a.controls.throttle = m.throttle;
  a.controls.brake = m.brake;
  a.controls.steer = m.car_steer;
  a.controls.handbrake = m.handbrake;
  a.controls.gear = m.gear;
  for (int k = 0; k < 4; ++k) a.controls.wheel_torque[k] = m.wheel_torque[k];
  a.steps = m.steps;
  a.mode = m.mode;
  a.rate = m.rate;
  a.publish_rate = m.publish_rate;
  a.reason = m.reason;
  a.epoch = m.epoch;
  return a;
}

session::Replica fromMessage(const groundsim::replica_t& m) {
  session::Replica r;
  r.kind = static_cast<session::Replica::Kind>(m.kind);
  r.session_id = m.session_id;
  r.epoch = m.epoch;
  r.tick = m.tick;
  r.applied_seq = m.applied_seq;
  r.frame_seq = m.frame_seq;
  r.meta = m.meta;
  r.data.assign(m.data.begin(), m.data.end());
  return r;
}

groundsim::replica_t toMessage(const session::Replica& r) {
  groundsim::replica_t m{};
  m.session_id = r.session_id;
  m.epoch = r.epoch;
  m.kind = static_cast<int8_t>(r.kind);
  m.tick = r.tick;
  m.applied_seq = r.applied_seq;
  m.frame_seq = r.frame_seq;
  m.meta = r.meta;
  m.data.assign(r.data.begin(), r.data.end());
  m.nbytes = static_cast<int32_t>(m.data.size());
  return m;
}

session::SessionInfo fromMessage(const groundsim::session_info_t& m) {
  session::SessionInfo s;
  s.session_id = m.session_id;
  s.name = m.name;
  s.mode = static_cast<session::Mode>(m.mode);
  s.status = static_cast<session::Status>(m.status);
  s.reason = m.status_reason;
  s.rate = m.rate;
  s.publish_rate = m.publish_rate;
  s.t = m.utime * 1e-6;
  s.tick = m.tick;
  s.seq = m.seq;
  s.vehicle_names = m.vehicle_names;
  s.idle_s = m.idle_s;
  s.dt = m.dt;
  for (auto w : m.wheel_counts) s.wheel_counts.push_back(w);
  s.control_period = m.control_period;
  s.num_envs = m.num_envs;
  s.server_id = m.server_id;
  s.epoch = m.epoch;
  return s;
}

}  // namespace groundsim::net

namespace groundsim::net {
namespace {

// LCM's encoding: big-endian, the fields in their declared order after the
// type's 8-byte fingerprint, strings as an int32 length (with the NUL) and
// their bytes.
std::int64_t readI64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];
  return static_cast<std::int64_t>(v);
}

}  // namespace

std::optional<StateHead> peekState(const void* data, int size) {
  const auto* b = static_cast<const std::uint8_t*>(data);
  // fingerprint, utime, seq, the session id's length
  if (size < 8 + 8 + 8 + 4 || readI64(b) != groundsim::state_t::getHash()) return std::nullopt;
  StateHead h;
  h.seq = readI64(b + 16);
  const std::int64_t len = static_cast<std::int32_t>((std::uint32_t{b[24]} << 24) | (std::uint32_t{b[25]} << 16) |
                                                     (std::uint32_t{b[26]} << 8) | std::uint32_t{b[27]});
  const std::int64_t tick_at = 28 + len + 8;  // after the id and t
  // epoch and error_estimate are the last 16 bytes
  if (len < 1 || tick_at + 8 > size - 16) return std::nullopt;
  h.tick = readI64(b + tick_at);
  h.epoch = readI64(b + size - 16);
  return h;
}

}  // namespace groundsim::net
