// experiments::BatchEnv over several vectorised sessions at once: N
// environments split into K shards, each a RemoteVecEnv. In a fleet
// (docs/fleet.md) every create is placed by the fleet, so with "spread" the
// shards land on different servers. Env i is env i - offset(k) of shard k;
// a seeded reset seeds shard k with seed + offset(k), so env i is seeded
// with seed + i as in makeVecEnv: the same seed and actions give the same
// bits whatever the placement. A step sends every shard its request at once
// (a thread per shard) and waits for all. When a shard's server is gone
// during a step (no heartbeat from it for kHeartbeatTimeout, or no reply),
// the shard is created again (the fleet places it on a live server) and
// reset, and the step returns its environments' reset observations with
// truncated set and reward 0: the training loop goes on (vectorised
// sessions are not replicated: docs/fleet.md). Other calls fail with
// RemoteError naming the shard.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "client/experiments/remote_vec_env.hpp"

namespace groundsim::experiments {

class ShardedVecEnv final : public BatchEnv {
 public:
  // shards in [1, num_envs]; the first num_envs % shards shards hold one env more.
  ShardedVecEnv(const std::string& scenario_text, int num_envs, int shards, RemoteVecOptions options = {});
  ~ShardedVecEnv() override;

  const Layout& layout() const override { return layout_; }
  void reset(std::optional<std::uint64_t> seed, float* obs) override;
  void resetEnv(int env, std::optional<std::uint64_t> seed, float* obs_rows) override;
  void step(const float* actions, float* obs, double* rewards, std::uint8_t* terminated,
            std::uint8_t* truncated) override;
  EnvInfo info(int row) const override;
  std::string snapshot(int env) const override;
  void restore(int env, const std::string& snapshot, float* obs_rows) override;
  void setRandomization(int env, const std::string& randomize_json) override;
  void drawn(double* out) const override;
  void render(int env, int width, int height, std::uint8_t* rgb) const override;
  void close() override;

  int shards() const { return static_cast<int>(shards_.size()); }

 private:
  int shardOf(int env) const;  // throws ExperimentError("env") out of range
  // f(k) for every shard at once; the first failure (by shard order) is rethrown
  template <class F>
  void everyShard(F f);
  // shard k's n environments created again (reset, observations into obs)
  std::unique_ptr<RemoteVecEnv> recreate(int k, int n, float* obs);

  std::string scenario_text_;
  RemoteVecOptions options_;
  std::vector<std::unique_ptr<RemoteVecEnv>> shards_;
  std::vector<int> offset_;  // first env of each shard, then num_envs
  Layout layout_;
};

}  // namespace groundsim::experiments
