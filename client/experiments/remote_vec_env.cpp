#include "remote_vec_env.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

#include <unistd.h>

#include <groundsim/event_t.hpp>
#include <groundsim/request_t.hpp>

#include "protocol/client_id.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "protocol/text.hpp"
#include "scenario/scenario.hpp"

namespace groundsim::experiments {
namespace {

using Clock = std::chrono::steady_clock;

std::int64_t wallMicros() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

Layout fromWire(const groundsim::env_layout_t& m) {
  Layout l;
  l.num_envs = m.num_envs;
  l.num_agents = m.num_agents;
  l.agents = m.agents;
  l.dt = m.dt;
  l.control_period = m.control_period;
  l.time_limit = m.time_limit;
  l.observation = m.observation;
  l.observation_low = m.observation_low;
  l.observation_high = m.observation_high;
  l.action = m.action;
  l.action_low = m.action_low;
  l.action_high = m.action_high;
  l.wheel_counts.assign(m.wheel_counts.begin(), m.wheel_counts.end());
  l.scenario_hash = m.scenario_hash;
  l.drawn.assign(m.drawn.begin(), m.drawn.end());
  return l;
}

// A refusal: the server names the field for bad input (an ExperimentError,
// as makeVecEnv throws); without a field it is the transport's or the
// server's own trouble.
[[noreturn]] void throwRefusal(const groundsim::vec_reply_t& r) {
  if (!r.field.empty()) {
    const std::string prefix = r.field + ": ";
    throw ExperimentError(r.field, r.error.rfind(prefix, 0) == 0 ? r.error.substr(prefix.size()) : r.error);
  }
  throw RemoteError("groundsim-server refused: " + r.error);
}

// The wire's int64 holds [0, 2^63), what makeVecEnv takes; said here so
// that 2^64 - 1 is not sent as -1.
std::string seedText(std::optional<std::uint64_t> seed) {
  if (seed && *seed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    return "must be in [0, 2^63), got " + std::to_string(*seed);
  return "";
}

}  // namespace

RemoteVecEnv::RemoteVecEnv(const std::string& scenario_text, int num_envs, RemoteVecOptions options)
    : options_(std::move(options)),
      // parts come in a burst: a deep socket buffer, as every subscriber that must not lose messages
      url_(net::withReceiveBuffer(options_.lcm_url)),
      lcm_(url_),
      watch_(lcm_) {
  if (!lcm_.good())
    throw RemoteError("cannot open LCM URL " + net::quoted(url_) +
                      " (no multicast route? e.g. `ip route add 224.0.0.0/4 dev lo`)");
  client_id_ = net::newClientId("vec");  // principal/instance (protocol/client_id.hpp)
  lcm_.subscribe(net::kVecReplyChannel, &RemoteVecEnv::onVecReply, this)->setQueueCapacity(net::kDeepQueue);
  lcm_.subscribe(net::kReplyChannel, &RemoteVecEnv::onReply, this)->setQueueCapacity(net::kDeepQueue);
  wants_.setClientId(client_id_);
  lcm_.subscribe(net::kAssetWantChannel, &RemoteVecEnv::onAssetWant, this)->setQueueCapacity(net::kDeepQueue);
  lcm_.subscribe(net::kEventChannel, &RemoteVecEnv::onEvent, this)->setQueueCapacity(net::kDeepQueue);

  const groundsim::vec_reply_t r = create(scenario_text, num_envs);
  if (r.nsessions < 1 || r.sessions[0].nlayout < 1)
    throw RemoteError("create: the server's reply carries no layout (an older groundsim-server?)");
  session_id_ = r.session_id;
  server_id_ = r.sessions[0].server_id;
  token_ = r.token;
  layout_ = fromWire(r.sessions[0].layout[0]);
  if (layout_.num_agents < 1) throw RemoteError("create: the server's layout has " + std::to_string(layout_.num_agents) + " agents");
  if (layout_.num_envs != num_envs)
    throw RemoteError("create: asked for " + std::to_string(num_envs) + " environments, the server made " +
                      std::to_string(layout_.num_envs));
  infos_.assign(static_cast<std::size_t>(layout_.rows()), EnvInfo{});
}

groundsim::vec_reply_t RemoteVecEnv::create(const std::string& scenario_text, int num_envs) {
  net::ScenarioWithAssets sent{scenario_text, {}};
  if (options_.send_files) {
    try {
      sent = net::withAssets(scenario_text, options_.files_dir);
    } catch (const scenario::ScenarioError& e) {
      throw ExperimentError("scenario_json", e.lines("; "));
    }
  }
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_CREATE;
  req.scenario_json = sent.json;
  req.num_envs = num_envs;
  for (int round = 0;; ++round) {
    bool missing = false;
    asset_error_.clear();
    groundsim::vec_reply_t r = call(req, options_.create_timeout_s, "create", &missing);
    drain();  // an event about a refused part comes before the reply
    if (!asset_error_.empty()) throw ExperimentError("assets", asset_error_);
    if (!missing) return r;
    if (sent.assets.empty() || round + 1 >= net::kAssetRounds)
      throw ExperimentError(r.field.empty() ? "assets" : r.field,
                            r.error + (sent.assets.empty() ? std::string(" (no files were sent: give the scenario as a "
                                                                         "path, or files_dir)")
                                                           : " (still missing after " +
                                                                 std::to_string(net::kAssetRounds) + " rounds)"));
    try {
      net::sendWantedParts(lcm_, client_id_, sent.assets, wants_.take(r.request_id));
    } catch (const std::exception& e) {
      throw RemoteError(std::string("create: sending the scenario's files: ") + e.what());
    }
  }
}

void RemoteVecEnv::onAssetWant(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  wants_.addDatagram(rbuf->data, static_cast<int>(rbuf->data_size));
}

void RemoteVecEnv::onEvent(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::event_t m;
  if (!net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.event_t").ok()) return;
  if (m.client_id == client_id_ && m.channel == net::kAssetChannel && asset_error_.empty()) asset_error_ = m.reason;
}

RemoteVecEnv::~RemoteVecEnv() {
  try {
    close();
  } catch (...) {
    // a server that is gone cannot stop the session; it reclaims it when idle
  }
}

void RemoteVecEnv::onVecReply(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::vec_reply_t m;
  if (!net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.vec_reply_t").ok()) return;
  if (m.client_id != client_id_ || m.request_id != assembler_.requestId() || assembler_.requestId() == 0) return;
  const std::string why = assembler_.add(m);
  if (!why.empty() && part_error_.empty()) part_error_ = why;
}

void RemoteVecEnv::onReply(const lcm::ReceiveBuffer* rbuf, const std::string&) {
  groundsim::reply_t m;
  if (!net::decodeMessage(rbuf->data, static_cast<int>(rbuf->data_size), m, "groundsim.reply_t").ok()) return;
  if (m.client_id == client_id_ && m.request_id == stop_waiting_) stop_reply_ = std::move(m);
}

groundsim::vec_reply_t RemoteVecEnv::call(groundsim::vec_request_t req, double timeout_s, const char* what,
                                          bool* missing_assets) const {
  req.utime = wallMicros();
  req.seq = next_id_;
  req.request_id = next_id_++;
  req.client_id = client_id_;
  req.session_id = session_id_;
  req.token = token_;
  req.nactions = static_cast<int32_t>(req.actions.size());
  req.snapshot_size = static_cast<int32_t>(req.snapshot.size());
  drain();
  assembler_ = net::VecAssembler(req.request_id);
  part_error_.clear();
  if (lcm_.publish(net::kVecRequestChannel, &req) != 0) throw RemoteError(std::string(what) + ": cannot publish on " + url_);
  const auto start = Clock::now();
  auto last_part = start;
  int parts_seen = 0;
  while (!assembler_.complete()) {
    if (!part_error_.empty())
      throw RemoteError(std::string(what) + ": request " + std::to_string(req.request_id) + ": " + part_error_);
    if (watch_.lost()) throw RemoteError(std::string(what) + ": " + watch_.lostMessage(url_));
    // in a fleet the others' heartbeats go on: this session's server must beat
    if (!server_id_.empty() && watch_.silenceOf(server_id_) > watch_.timeoutOf(server_id_))
      throw RemoteError(std::string(what) + ": no heartbeat from server " + server_id_ + " (the owner of session " +
                        session_id_ + ") for " + std::to_string(watch_.silenceOf(server_id_)).substr(0, 4) + " s");
    const int got = assembler_.parts() - static_cast<int>(assembler_.missing().size());
    if (got != parts_seen) {
      parts_seen = got;
      last_part = Clock::now();
    }
    // before the first part: the request's timeout; after one, the rest come in a burst
    if (assembler_.started() ? secondsSince(last_part) > options_.part_gap_s : secondsSince(start) > timeout_s) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.1f", secondsSince(start));
      throw RemoteError(std::string(what) + ": request " + std::to_string(req.request_id) + " of session " +
                        (session_id_.empty() ? std::string("(new)") : session_id_) + ": missing " +
                        assembler_.missingText() + " of the reply after " + buf + " s on " + url_ +
                        (assembler_.started() ? " (lost datagrams: a larger recv_buf_size helps)"
                         : watch_.heartbeats() > 0 ? " (the server's heartbeat is there: busy or dropped)"
                                                   : " (is groundsim-server running with the same --lcm-url?)"));
    }
    lcm_.handleTimeout(assembler_.started() ? 20 : 100);
  }
  groundsim::vec_reply_t r = assembler_.take();
  assembler_ = net::VecAssembler(0);
  if (!r.ok && missing_assets && r.error_code == groundsim::asset_want_t::ERR_MISSING_ASSETS) {
    *missing_assets = true;
    return r;
  }
  if (!r.ok) throwRefusal(r);
  return r;
}

// Handles what arrived while the caller was busy elsewhere (heartbeats
// queued in the socket): a client that did not call for longer than the
// heartbeat timeout must not take a living server for a dead one.
void RemoteVecEnv::drain() const {
  for (int i = 0; i < 100000 && lcm_.handleTimeout(0) > 0; ++i) {
  }
}

void RemoteVecEnv::checkOpen(const char* what) const {
  if (closed_) throw RemoteError(std::string(what) + ": the environment was closed");
}

void RemoteVecEnv::checkEnv(int env) const {
  if (env < 0 || env >= layout_.num_envs)
    throw ExperimentError("env", std::to_string(env) + " is outside [0, " + std::to_string(layout_.num_envs - 1) + "]");
}

void RemoteVecEnv::takeEnvs(const groundsim::vec_reply_t& r, float* obs, double* rewards, std::uint8_t* terminated,
                            std::uint8_t* truncated) {
  const int o = layout_.obsSize();
  if (r.obs_size != o || r.env_begin < 0 || r.env_begin + r.env_count > layout_.rows())
    throw RemoteError("reply of request " + std::to_string(r.request_id) + " does not fit the layout");
  if (obs && !r.obs.empty()) std::memcpy(obs, r.obs.data(), r.obs.size() * sizeof(float));
  for (int i = 0; i < r.env_count; ++i) {
    if (rewards) rewards[i] = r.rewards[i];
    if (terminated) terminated[i] = static_cast<std::uint8_t>(r.terminated[i]);
    if (truncated) truncated[i] = static_cast<std::uint8_t>(r.truncated[i]);
    EnvInfo& info = infos_[r.env_begin + i];
    info.episode = r.episode[i];
    info.episode_steps = r.episode_steps[i];
    info.episode_return = r.episode_return[i];
    info.diverged = r.diverged[i] != 0;
    info.active = r.active[i] != 0;
  }
}

void RemoteVecEnv::reset(std::optional<std::uint64_t> seed, float* obs) {
  checkOpen("reset");
  if (const std::string why = seedText(seed); !why.empty()) throw ExperimentError("seed", why);
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_RESET;
  req.has_seed = seed.has_value();
  req.seed = seed ? static_cast<std::int64_t>(*seed) : 0;
  takeEnvs(call(req, options_.timeout_s, "reset"), obs, nullptr, nullptr, nullptr);
}

void RemoteVecEnv::resetEnv(int env, std::optional<std::uint64_t> seed, float* obs_row) {
  checkOpen("reset_env");
  checkEnv(env);
  if (const std::string why = seedText(seed); !why.empty()) throw ExperimentError("seed", why);
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_RESET_ENV;
  req.env = env;
  req.has_seed = seed.has_value();
  req.seed = seed ? static_cast<std::int64_t>(*seed) : 0;
  takeEnvs(call(req, options_.timeout_s, "reset_env"), obs_row, nullptr, nullptr, nullptr);
}

void RemoteVecEnv::step(const float* actions, float* obs, double* rewards, std::uint8_t* terminated,
                        std::uint8_t* truncated) {
  checkOpen("step");
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_STEP;
  req.actions.assign(actions, actions + static_cast<std::size_t>(layout_.rows()) * layout_.actionSize());
  takeEnvs(call(std::move(req), options_.timeout_s, "step"), obs, rewards, terminated, truncated);
}

EnvInfo RemoteVecEnv::info(int row) const {
  if (row < 0 || row >= layout_.rows())
    throw ExperimentError("row", std::to_string(row) + " is outside [0, " + std::to_string(layout_.rows() - 1) + "]");
  return infos_[static_cast<std::size_t>(row)];
}

std::string RemoteVecEnv::snapshot(int env) const {
  checkOpen("snapshot");
  checkEnv(env);
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_SNAPSHOT;
  req.env = env;
  const groundsim::vec_reply_t r = call(req, options_.timeout_s, "snapshot");
  return std::string(r.snapshot.begin(), r.snapshot.end());
}

void RemoteVecEnv::restore(int env, const std::string& snapshot, float* obs_row) {
  checkOpen("restore");
  checkEnv(env);
  if (snapshot.size() > net::kMaxSnapshotBytes)
    throw ExperimentError("snapshot", std::to_string(snapshot.size()) + " bytes, at most " +
                                          std::to_string(net::kMaxSnapshotBytes));
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_RESTORE;
  req.env = env;
  req.snapshot.assign(snapshot.begin(), snapshot.end());
  takeEnvs(call(std::move(req), options_.timeout_s, "restore"), obs_row, nullptr, nullptr, nullptr);
}

void RemoteVecEnv::setRandomization(int env, const std::string& randomize_json) {
  checkOpen("set_randomization");
  if (env != -1) checkEnv(env);
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_RANDOMIZE;
  req.env = env;
  req.scenario_json = randomize_json;
  call(std::move(req), options_.timeout_s, "set_randomization");
}

void RemoteVecEnv::drawn(double* out) const {
  checkOpen("drawn");
  groundsim::vec_request_t req{};
  req.op = groundsim::vec_request_t::OP_DRAWN;
  const groundsim::vec_reply_t r = call(req, options_.timeout_s, "drawn");
  const std::size_t want = static_cast<std::size_t>(layout_.num_envs) * layout_.drawnSize() * sizeof(double);
  if (r.snapshot.size() != want)
    throw RemoteError("drawn: reply of request " + std::to_string(r.request_id) + " holds " +
                      std::to_string(r.snapshot.size()) + " bytes, the layout needs " + std::to_string(want));
  // float64 little-endian, as the server wrote them (session/vec_session.cpp)
  for (std::size_t k = 0; k < want / sizeof(double); ++k) {
    std::uint64_t bits = 0;
    for (int b = 0; b < 8; ++b) bits |= static_cast<std::uint64_t>(r.snapshot[k * 8 + b]) << (8 * b);
    std::memcpy(out + k, &bits, sizeof bits);
  }
}

void RemoteVecEnv::render(int, int, int, std::uint8_t*) const {
  throw ExperimentError("render_mode", "a remote environment does not render: its state lives in the server; "
                                       "run the same seed with make_vec in process (bit for bit the same run) to render it");
}

void RemoteVecEnv::close() {
  if (closed_ || session_id_.empty()) return;
  closed_ = true;
  groundsim::request_t req{};
  req.utime = wallMicros();
  req.seq = next_id_;
  req.request_id = next_id_++;
  req.client_id = client_id_;
  req.session_id = session_id_;
  req.token = token_;
  req.op = groundsim::request_t::OP_STOP;
  drain();
  stop_waiting_ = req.request_id;
  stop_reply_.reset();
  if (lcm_.publish(net::kRequestChannel, &req) != 0) throw RemoteError("close: cannot publish on " + url_);
  const auto start = Clock::now();
  while (!stop_reply_) {
    if (watch_.lost()) throw RemoteError("close: " + watch_.lostMessage(url_));
    // in a fleet: the session's own server is gone (a lost shard is closed so)
    if (!server_id_.empty() && watch_.silenceOf(server_id_) > watch_.timeoutOf(server_id_))
      throw RemoteError("close: no heartbeat from server " + server_id_ + " (the owner of session " + session_id_ +
                        "): the session went with it");
    if (secondsSince(start) > options_.timeout_s)
      throw RemoteError("close: no reply to the stop of session " + session_id_ + " on " + url_);
    lcm_.handleTimeout(100);
  }
  if (!stop_reply_->ok) throw RemoteError("close: groundsim-server refused: " + stop_reply_->error);
}

}  // namespace groundsim::experiments
