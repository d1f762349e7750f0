#include "vec_parts.hpp"

#include <algorithm>
#include <stdexcept>

namespace groundsim::net {
namespace {

using groundsim::vec_reply_t;

// The part's header: everything but the per-env arrays and snapshot bytes.
vec_reply_t headerOf(const vec_reply_t& w) {
  vec_reply_t h = w;
  h.nsessions = 0;
  h.sessions.clear();
  h.env_begin = 0;
  h.env_count = 0;
  h.nobs = 0;
  h.obs.clear();
  h.rewards.clear();
  h.terminated.clear();
  h.truncated.clear();
  h.episode.clear();
  h.episode_steps.clear();
  h.episode_return.clear();
  h.diverged.clear();
  h.active.clear();
  h.snapshot_offset = 0;
  h.nsnapshot = 0;
  h.snapshot.clear();
  return h;
}

template <class T>
std::vector<T> slice(const std::vector<T>& v, std::size_t begin, std::size_t count) {
  begin = std::min(begin, v.size());
  count = std::min(count, v.size() - begin);
  return std::vector<T>(v.begin() + begin, v.begin() + begin + count);
}

template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

std::size_t vecBytesPerEnv(int obs_size) {
  return static_cast<std::size_t>(std::max(0, obs_size)) * sizeof(float) + 8 + 1 + 1 + 8 + 8 + 8 + 1 + 1;
}

std::vector<vec_reply_t> splitVecReply(const vec_reply_t& whole, std::size_t max_bytes) {
  const vec_reply_t header = headerOf(whole);
  const std::size_t base = static_cast<std::size_t>(header.getEncodedSize());
  const std::size_t per_env = vecBytesPerEnv(whole.obs_size);
  vec_reply_t first = header;
  first.nsessions = whole.nsessions;
  first.sessions = whole.sessions;
  const std::size_t first_base = static_cast<std::size_t>(first.getEncodedSize());

  std::vector<vec_reply_t> parts;
  const std::size_t envs = static_cast<std::size_t>(std::max(0, whole.env_count));
  const std::size_t obs = static_cast<std::size_t>(std::max(0, whole.obs_size));
  const std::size_t blob = whole.snapshot.size();
  std::size_t env = 0, byte = 0;
  do {
    vec_reply_t p = parts.empty() ? first : header;
    const std::size_t used = parts.empty() ? first_base : base;
    std::size_t room = max_bytes > used ? max_bytes - used : 0;
    // environments first, at least one per part while any are left
    std::size_t n_env = std::min(envs - env, room / per_env);
    if (n_env == 0 && env < envs) n_env = 1;
    room = room > n_env * per_env ? room - n_env * per_env : 0;
    // then snapshot bytes in what room is left, at least one once the envs are done
    std::size_t n_byte = std::min(blob - byte, room);
    if (n_byte == 0 && env + n_env == envs && byte < blob) n_byte = std::min<std::size_t>(blob - byte, 1);
    p.env_begin = static_cast<int32_t>(whole.env_begin + env);
    p.env_count = static_cast<int32_t>(n_env);
    p.nobs = static_cast<int32_t>(n_env * obs);
    p.obs = slice(whole.obs, env * obs, n_env * obs);
    p.rewards = slice(whole.rewards, env, n_env);
    p.terminated = slice(whole.terminated, env, n_env);
    p.truncated = slice(whole.truncated, env, n_env);
    p.episode = slice(whole.episode, env, n_env);
    p.episode_steps = slice(whole.episode_steps, env, n_env);
    p.episode_return = slice(whole.episode_return, env, n_env);
    p.diverged = slice(whole.diverged, env, n_env);
    p.active = slice(whole.active, env, n_env);
    p.snapshot_offset = static_cast<int32_t>(byte);
    p.nsnapshot = static_cast<int32_t>(n_byte);
    p.snapshot = slice(whole.snapshot, byte, n_byte);
    env += n_env;
    byte += n_byte;
    parts.push_back(std::move(p));
  } while (env < envs || byte < blob);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    parts[i].part = static_cast<int32_t>(i);
    parts[i].nparts = static_cast<int32_t>(parts.size());
  }
  return parts;
}

std::string VecAssembler::add(const vec_reply_t& p) {
  if (p.nparts < 1 || p.part < 0 || p.part >= p.nparts)
    return "part " + std::to_string(p.part) + " of " + std::to_string(p.nparts) + " is not a part";
  if (nparts_ == 0) {
    nparts_ = p.nparts;
    parts_.assign(static_cast<std::size_t>(nparts_), std::nullopt);
  } else if (p.nparts != nparts_) {
    return "part " + std::to_string(p.part) + " says " + std::to_string(p.nparts) + " parts, the first said " +
           std::to_string(nparts_);
  }
  auto& slot = parts_[static_cast<std::size_t>(p.part)];
  if (slot) return "part " + std::to_string(p.part) + " arrived twice";
  for (const auto& q : parts_) {
    if (!q) continue;
    if (q->num_envs != p.num_envs || q->obs_size != p.obs_size || q->snapshot_total != p.snapshot_total)
      return "part " + std::to_string(p.part) + " disagrees with part " + std::to_string(q->part) +
             " on num_envs, obs_size or snapshot_total";
  }
  const bool sizes_ok = p.env_count >= 0 && p.env_begin >= 0 && p.env_begin <= p.num_envs - p.env_count &&
                        p.nobs == p.env_count * p.obs_size && p.nsnapshot >= 0 && p.snapshot_offset >= 0 &&
                        p.snapshot_offset <= p.snapshot_total - p.nsnapshot;
  if (!sizes_ok) return "part " + std::to_string(p.part) + " has ranges outside the reply";
  slot = p;
  ++received_;
  return "";
}

std::vector<int> VecAssembler::missing() const {
  std::vector<int> m;
  for (int i = 0; i < nparts_; ++i)
    if (!parts_[static_cast<std::size_t>(i)]) m.push_back(i);
  return m;
}

std::string VecAssembler::missingText() const {
  if (nparts_ == 0) return "every part (none arrived)";
  const std::vector<int> m = missing();
  std::string s = m.size() == 1 ? "part " : "parts ";
  for (std::size_t i = 0; i < m.size() && i < 20; ++i) s += (i ? ", " : "") + std::to_string(m[i]);
  if (m.size() > 20) s += " and " + std::to_string(m.size() - 20) + " more";
  return s + " of " + std::to_string(nparts_);
}

vec_reply_t VecAssembler::take() {
  vec_reply_t w = headerOf(*parts_.front());
  // parts in env order (the server sends them so, but a reordered arrival must not matter)
  std::vector<const vec_reply_t*> order;
  for (const auto& p : parts_) order.push_back(&*p);
  std::stable_sort(order.begin(), order.end(), [](const vec_reply_t* a, const vec_reply_t* b) {
    return a->env_begin != b->env_begin ? a->env_begin < b->env_begin : a->snapshot_offset < b->snapshot_offset;
  });
  int next_env = -1;
  std::int32_t next_byte = 0;
  for (const vec_reply_t* p : order) {
    if (p->nsessions > 0) {
      w.nsessions = p->nsessions;
      w.sessions = p->sessions;
    }
    if (p->env_count > 0) {
      if (next_env < 0) next_env = w.env_begin = p->env_begin;
      if (p->env_begin != next_env) throw std::runtime_error("vec reply parts overlap or leave a gap");
      next_env += p->env_count;
      w.env_count += p->env_count;
      append(w.obs, p->obs);
      append(w.rewards, p->rewards);
      append(w.terminated, p->terminated);
      append(w.truncated, p->truncated);
      append(w.episode, p->episode);
      append(w.episode_steps, p->episode_steps);
      append(w.episode_return, p->episode_return);
      append(w.diverged, p->diverged);
      append(w.active, p->active);
    }
  }
  std::vector<const vec_reply_t*> by_byte(order);
  std::stable_sort(by_byte.begin(), by_byte.end(),
                   [](const vec_reply_t* a, const vec_reply_t* b) { return a->snapshot_offset < b->snapshot_offset; });
  for (const vec_reply_t* p : by_byte) {
    if (p->nsnapshot == 0) continue;
    if (p->snapshot_offset != next_byte) throw std::runtime_error("vec reply snapshot parts overlap or leave a gap");
    next_byte += p->nsnapshot;
    append(w.snapshot, p->snapshot);
  }
  if (next_byte != w.snapshot_total) throw std::runtime_error("vec reply snapshot is incomplete");
  w.nobs = static_cast<int32_t>(w.obs.size());
  w.nsnapshot = static_cast<int32_t>(w.snapshot.size());
  w.part = 0;
  w.nparts = 1;
  nparts_ = received_ = 0;
  parts_.clear();
  return w;
}

}  // namespace groundsim::net
