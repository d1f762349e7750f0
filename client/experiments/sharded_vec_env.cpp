#include "client/experiments/sharded_vec_env.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <thread>

namespace groundsim::experiments {

ShardedVecEnv::ShardedVecEnv(const std::string& scenario_text, int num_envs, int shards, RemoteVecOptions options)
    : scenario_text_(scenario_text), options_(options) {
  if (shards < 1 || shards > num_envs)
    throw ExperimentError("shards", "must be in [1, num_envs = " + std::to_string(num_envs) + "], got " +
                                        std::to_string(shards));
  offset_.push_back(0);
  for (int k = 0; k < shards; ++k) offset_.push_back(offset_.back() + num_envs / shards + (k < num_envs % shards));
  // one create after another: each is placed by the fleet knowing of the ones before
  for (int k = 0; k < shards; ++k) {
    try {
      shards_.push_back(std::make_unique<RemoteVecEnv>(scenario_text, offset_[k + 1] - offset_[k], options));
    } catch (...) {
      close();
      throw;
    }
  }
  layout_ = shards_.front()->layout();
  layout_.num_envs = num_envs;
}

ShardedVecEnv::~ShardedVecEnv() {
  try {
    close();
  } catch (...) {
  }
}

template <class F>
void ShardedVecEnv::everyShard(F f) {
  const int n = shards();
  std::vector<std::exception_ptr> errors(n);
  std::vector<std::thread> threads;
  threads.reserve(n);
  for (int k = 0; k < n; ++k)
    threads.emplace_back([&, k] {
      try {
        f(k);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  for (auto& t : threads) t.join();
  for (int k = 0; k < n; ++k) {
    if (!errors[k]) continue;
    try {
      std::rethrow_exception(errors[k]);
    } catch (const RemoteError& e) {
      throw RemoteError("shard " + std::to_string(k) + " (session " + shards_[k]->sessionId() + "): " + e.what());
    }
  }
}

int ShardedVecEnv::shardOf(int env) const {
  if (env < 0 || env >= layout_.num_envs)
    throw ExperimentError("env", std::to_string(env) + " is outside [0, " + std::to_string(layout_.num_envs) + ")");
  int k = 0;
  while (offset_[k + 1] <= env) ++k;
  return k;
}

void ShardedVecEnv::reset(std::optional<std::uint64_t> seed, float* obs) {
  const int rows = layout_.num_agents * layout_.obsSize();
  everyShard([&](int k) {
    std::optional<std::uint64_t> s;
    if (seed) s = *seed + static_cast<std::uint64_t>(offset_[k]);
    shards_[k]->reset(s, obs + static_cast<std::size_t>(offset_[k]) * rows);
  });
}

void ShardedVecEnv::resetEnv(int env, std::optional<std::uint64_t> seed, float* obs_rows) {
  const int k = shardOf(env);
  shards_[k]->resetEnv(env - offset_[k], seed, obs_rows);
}

void ShardedVecEnv::step(const float* actions, float* obs, double* rewards, std::uint8_t* terminated,
                         std::uint8_t* truncated) {
  const std::size_t agents = layout_.num_agents, na = agents * layout_.actionSize(), no = agents * layout_.obsSize();
  everyShard([&](int k) {
    const std::size_t e = offset_[k];
    try {
      shards_[k]->step(actions + e * na, obs + e * no, rewards + e * agents, terminated + e * agents,
                       truncated + e * agents);
    } catch (const RemoteError& lost) {
      // its server is gone: the shard again, elsewhere; its episodes end truncated
      const int n = offset_[k + 1] - offset_[k];
      std::fprintf(stderr, "groundsim: shard %d (session %s) lost (%s): created again, its %d environments truncated\n",
                   k, shards_[k]->sessionId().c_str(), lost.what(), n);
      shards_[k] = recreate(k, n, obs + e * no);
      const std::size_t rows = static_cast<std::size_t>(n) * agents;
      std::fill(rewards + e * agents, rewards + e * agents + rows, 0.0);
      std::fill(terminated + e * agents, terminated + e * agents + rows, std::uint8_t{0});
      std::fill(truncated + e * agents, truncated + e * agents + rows, std::uint8_t{1});
    }
  });
}

// A lost shard's environments, again on a server that beats (the fleet
// places the create; a dead one is not placed on once it has been silent
// for 3.5 heartbeat periods). A create that itself fails (its server died
// too, the fleet's etcd was electing a leader) is tried twice more.
std::unique_ptr<RemoteVecEnv> ShardedVecEnv::recreate(int k, int n, float* obs) {
  for (int attempt = 1;; ++attempt) {
    try {
      auto fresh = std::make_unique<RemoteVecEnv>(scenario_text_, n, options_);
      fresh->reset(std::nullopt, obs);
      return fresh;
    } catch (const RemoteError& e) {
      if (attempt == 3) throw;
      std::fprintf(stderr, "groundsim: shard %d: creating it again failed (%s): trying again\n", k, e.what());
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
  }
}

EnvInfo ShardedVecEnv::info(int row) const {
  const int env = row / layout_.num_agents;
  const int k = shardOf(env);
  return shards_[k]->info(row - offset_[k] * layout_.num_agents);
}

std::string ShardedVecEnv::snapshot(int env) const {
  const int k = shardOf(env);
  return shards_[k]->snapshot(env - offset_[k]);
}

void ShardedVecEnv::restore(int env, const std::string& snapshot, float* obs_rows) {
  const int k = shardOf(env);
  shards_[k]->restore(env - offset_[k], snapshot, obs_rows);
}

void ShardedVecEnv::setRandomization(int env, const std::string& randomize_json) {
  if (env == -1) {
    for (auto& s : shards_) s->setRandomization(-1, randomize_json);
    return;
  }
  const int k = shardOf(env);
  shards_[k]->setRandomization(env - offset_[k], randomize_json);
}

void ShardedVecEnv::drawn(double* out) const {
  const std::size_t d = layout_.drawnSize();
  for (int k = 0; k < shards(); ++k) shards_[k]->drawn(out + static_cast<std::size_t>(offset_[k]) * d);
}

void ShardedVecEnv::render(int env, int width, int height, std::uint8_t* rgb) const {
  const int k = shardOf(env);
  shards_[k]->render(env - offset_[k], width, height, rgb);
}

void ShardedVecEnv::close() {
  for (auto& s : shards_) s->close();
}

}  // namespace groundsim::experiments
