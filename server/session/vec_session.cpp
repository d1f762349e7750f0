#include "vec_session.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "answers.hpp"
#include "token.hpp"

namespace groundsim::session {

using experiments::ExperimentError;

namespace {
// Wrong or non-finite actions are bad controls; wrong envs, seeds and snapshots bad requests.
ErrorCode codeForField(const std::string& field) {
  return field.rfind("actions", 0) == 0 ? ErrorCode::BadControl : ErrorCode::BadRequest;
}
}  // namespace

std::string reasonOf(const ExperimentError& e) {
  const std::string w = e.what();
  const std::string prefix = e.field() + ": ";
  return w.rfind(prefix, 0) == 0 ? w.substr(prefix.size()) : w;
}

std::string checkVecRequest(const VecRequest& r, const experiments::Layout& layout, std::string& field) {
  const int n = layout.num_envs, rows = layout.rows();
  const int a = layout.actionSize();
  auto envInRange = [&]() -> std::string {
    if (r.env >= 0 && r.env < n) return "";
    field = "env";
    return std::to_string(r.env) + " is outside [0, " + std::to_string(n - 1) + "]";
  };
  switch (r.op) {
    case VecOp::Step: {
      const std::size_t want = static_cast<std::size_t>(rows) * static_cast<std::size_t>(a);
      if (r.actions.size() != want) {
        field = "actions";
        return std::to_string(r.actions.size()) + " values, the session needs rows (num_envs x num_agents) x "
               "action_size = " + std::to_string(rows) + " x " + std::to_string(a) + " = " + std::to_string(want);
      }
      for (std::size_t k = 0; k < want; ++k)
        if (!std::isfinite(r.actions[k])) {
          field = "actions[" + std::to_string(k / a) + "][" + std::to_string(k % a) + "]";
          // as makeVecEnv words it
          return std::string("must be finite, got ") +
                 (std::isnan(r.actions[k]) ? "nan" : r.actions[k] > 0 ? "inf" : "-inf") + " (" +
                 layout.action[k % a] + ")";
        }
      return "";
    }
    case VecOp::Reset:
    case VecOp::ResetEnv:
      if (r.op == VecOp::ResetEnv) {
        const std::string why = envInRange();
        if (!why.empty()) return why;
      }
      if (r.has_seed && r.seed < 0) {  // the wire's int64 holds [0, 2^63), as makeVecEnv takes
        field = "seed";
        return "must be in [0, 2^63), got " + std::to_string(r.seed);
      }
      return "";
    case VecOp::Snapshot:
    case VecOp::Drawn:
      return r.op == VecOp::Snapshot ? envInRange() : "";
    case VecOp::Randomize:
      return r.env == -1 ? "" : envInRange();
    case VecOp::Restore: {
      const std::string why = envInRange();
      if (!why.empty()) return why;
      if (r.snapshot.empty()) {
        field = "snapshot";
        return "empty";
      }
      return "";
    }
    case VecOp::Create:
      break;
  }
  field = "op";
  return std::string(vecOpName(r.op)) + " is not a request to an existing session";
}

VecSession::VecSession(VecSetup setup, std::unique_ptr<experiments::BatchEnv> env, Output& out, TimePoint now,
                       const SessionClock& clock)
    : HostedSession(Kind::Vectorised, setup.id, setup.token, now),
      setup_(std::move(setup)),
      out_(out),
      clock_(clock),
      env_(std::move(env)),
      layout_(std::make_shared<const experiments::Layout>(env_->layout())) {
  const int n = layout_->num_envs, rows = layout_->rows();
  obs_.assign(static_cast<std::size_t>(rows) * layout_->obsSize(), 0.0f);
  rewards_.assign(rows, 0.0);
  terminated_.assign(rows, 0);
  truncated_.assign(rows, 0);
  info_.session_id = setup_.id;
  info_.name = setup_.name;
  info_.mode = Mode::Vectorised;
  info_.rate = 0.0;
  info_.publish_rate = 0.0;
  info_.vehicle_names = setup_.vehicle_names;
  info_.dt = layout_->dt;
  info_.wheel_counts = layout_->wheel_counts;
  info_.control_period = layout_->control_period;
  info_.num_envs = n;
  info_.layout = layout_;
  updateInfo();
}

void VecSession::post(VecRequest r) {
  std::lock_guard<std::mutex> lk(mailbox_mutex_);
  mailbox_.emplace_back(std::move(r));
}

void VecSession::stop(std::optional<ReplyTo> reply, std::string reason) {
  std::lock_guard<std::mutex> lk(mailbox_mutex_);
  mailbox_.emplace_back(StopCommand{std::move(reply), std::move(reason)});
}

SessionInfo VecSession::listing() const {
  std::lock_guard<std::mutex> lk(info_mutex_);
  return info_;
}

void VecSession::updateInfo() {
  std::lock_guard<std::mutex> lk(info_mutex_);
  info_.status = status_;
  info_.reason = reason_;
  info_.tick = tick_;
  info_.t = static_cast<double>(tick_) * layout_->control_period * layout_->dt;
}

// One request per run: a batched step is the slice (it cannot be divided),
// and the worker is handed back after it, so every session due meanwhile
// runs before this one's next request.
std::optional<TimePoint> VecSession::run(TimePoint) {
  std::optional<Command> cmd;
  bool more = false;
  {
    std::lock_guard<std::mutex> lk(mailbox_mutex_);
    if (!mailbox_.empty()) {
      cmd = std::move(mailbox_.front());
      mailbox_.pop_front();
    }
    more = !mailbox_.empty();
  }
  if (cmd) std::visit([&](const auto& c) { apply(c); }, *cmd);
  updateInfo();
  if (more) return clock_.now();
  return std::nullopt;
}

void VecSession::abandon(const char* why) noexcept {
  // run() catches everything per request; this is the scheduler's last resort
  try {
    status_ = Status::Diverged;
    reason_ = std::string("internal error: ") + why;
    updateInfo();
    out_.publishEvent(sessionEvent(setup_.id, Severity::Error, ErrorCode::Internal, reason_));
  } catch (...) {
  }
}

VecReply VecSession::replyFor(const VecRequest& r) const {
  VecReply reply;
  reply.op = r.op;
  reply.request_id = r.request_id;
  reply.client_id = r.client_id;
  reply.session_id = setup_.id;
  reply.num_envs = layout_->rows();  // the reply's arrays hold rows (environment x agent)
  reply.obs_size = layout_->obsSize();
  return reply;
}

void VecSession::refuse(const VecRequest& r, ErrorCode code, const std::string& field, const std::string& error) {
  VecReply reply = replyFor(r);
  reply.ok = false;
  reply.code = code;
  reply.field = field;
  reply.error = field.empty() ? error : field + ": " + error;
  reply.tick = tick_;
  Event e = refusalEvent(ReplyTo{Op::List, r.request_id, r.client_id}, setup_.id, code, reply.error);
  out_.publishEvent(e);
  out_.publishVecReply(reply);
}

void VecSession::fillEnvs(VecReply& reply, int begin, int count, const float* obs) const {
  const int o = layout_->obsSize();
  reply.env_begin = begin;
  reply.env_count = count;
  reply.obs.assign(obs, obs + static_cast<std::size_t>(count) * o);
  reply.infos.reserve(count);
  for (int i = 0; i < count; ++i) reply.infos.push_back(env_->info(begin + i));
  if (reply.op == VecOp::Step) {
    reply.rewards.assign(rewards_.begin() + begin, rewards_.begin() + begin + count);
    reply.terminated.assign(terminated_.begin() + begin, terminated_.begin() + begin + count);
    reply.truncated.assign(truncated_.begin() + begin, truncated_.begin() + begin + count);
  } else {  // a reset or restore starts an episode: reward 0, no flags
    reply.rewards.assign(count, 0.0);
    reply.terminated.assign(count, 0);
    reply.truncated.assign(count, 0);
  }
}

void VecSession::apply(const VecRequest& r) {
  if (status_ == Status::Stopped)
    return refuse(r, ErrorCode::UnknownSession, "session_id", "session " + setup_.id + " was stopped");
  try {
    std::string field;
    const std::string why = checkVecRequest(r, *layout_, field);
    if (!why.empty()) return refuse(r, codeForField(field), field, why);
    VecReply reply = replyFor(r);
    const int n = layout_->rows(), agents = layout_->num_agents;
    const int o = layout_->obsSize();
    const std::size_t first = static_cast<std::size_t>(r.env) * agents;  // ResetEnv, Restore: the env's first row
    std::optional<std::uint64_t> seed;
    if (r.has_seed) seed = static_cast<std::uint64_t>(r.seed);
    switch (r.op) {
      case VecOp::Step:
        env_->step(r.actions.data(), obs_.data(), rewards_.data(), terminated_.data(), truncated_.data());
        ++tick_;
        fillEnvs(reply, 0, n, obs_.data());
        break;
      case VecOp::Reset:
        env_->reset(seed, obs_.data());
        fillEnvs(reply, 0, n, obs_.data());
        break;
      case VecOp::ResetEnv:
        env_->resetEnv(r.env, seed, obs_.data() + first * o);
        fillEnvs(reply, static_cast<int>(first), agents, obs_.data() + first * o);
        break;
      case VecOp::Snapshot:
        reply.snapshot = env_->snapshot(r.env);
        reply.env_begin = r.env;
        break;
      case VecOp::Restore:
        env_->restore(r.env, r.snapshot, obs_.data() + first * o);
        fillEnvs(reply, static_cast<int>(first), agents, obs_.data() + first * o);
        break;
      case VecOp::Randomize:
        env_->setRandomization(r.env, r.scenario_json);
        break;
      case VecOp::Drawn: {
        std::vector<double> d(static_cast<std::size_t>(layout_->num_envs) * layout_->drawnSize());
        env_->drawn(d.data());
        reply.snapshot.resize(d.size() * sizeof(double));
        for (std::size_t k = 0; k < d.size(); ++k) {  // float64 little-endian
          std::uint64_t bits = 0;
          std::memcpy(&bits, &d[k], sizeof bits);
          for (int b = 0; b < 8; ++b) reply.snapshot[k * 8 + b] = static_cast<char>((bits >> (8 * b)) & 0xff);
        }
        break;
      }
      case VecOp::Create:
        break;
    }
    reply.tick = tick_;
    out_.publishVecReply(reply);
  } catch (const ExperimentError& e) {
    refuse(r, codeForField(e.field()), e.field(), reasonOf(e));
  } catch (const std::exception& e) {
    refuse(r, ErrorCode::Internal, "", std::string("internal error: ") + e.what());
  } catch (...) {
    refuse(r, ErrorCode::Internal, "", "internal error: unknown exception");
  }
}

void VecSession::apply(const StopCommand& c) {
  status_ = Status::Stopped;
  reason_ = c.reason;
  updateInfo();
  out_.publishEvent(sessionEvent(setup_.id, Severity::Info, ErrorCode::None, "stopped: " + c.reason));
  if (c.reply) {
    Reply reply = makeReply(*c.reply, setup_.id, true);
    reply.sessions.push_back(info(clock_.now()));
    out_.publishReply(reply);
  }
  env_->close();
}

}  // namespace groundsim::session
