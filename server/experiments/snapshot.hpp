// The snapshot of one environment as bytes, for the embedded API and the
// server (a restore into another process of the same scenario continues
// bit for bit). Layout, all little-endian:
//
//   magic   8 bytes  "GSENVSNP"
//   version u32      kSnapshotVersion
//   hash    u32 length + bytes: Layout::scenario_hash of the scenario
//   payload EnvSnapshot: the physics State (y, time, tick, step, energy
//           bookkeeping, wheel and road-car controls, road-car runtime,
//           health), the random stream, episode counters (the returns,
//           finished and active flags per agent), the previous
//           action, the drawn initial offsets and parameters, the ranges
//           the next resets draw from (the task's `randomize` as JSON
//           text: a curriculum may have changed them), the last
//           observation and the agents' progress along a task's track;
//           doubles as their IEEE-754 bits, vectors and text
//           as a u32 count then the elements
//   check   u64      FNV-1a 64 of every byte before it
//
// decodeSnapshot checks the magic, version, hash, checksum and that every
// count fits the bytes left, before allocating anything; the sizes against
// the model are checked by the environment that loads it (env.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "physics/core/state.hpp"

namespace groundsim::experiments {

// 2: the ranges (a curriculum's) and the agents' counters travel with the env
// 3: the agents' progress along a task's track (TrackProgress)
inline constexpr std::uint32_t kSnapshotVersion = 3;

struct EnvSnapshot {
  State state;
  std::uint64_t rng = 0;
  std::int64_t episode = 0, episode_steps = 0;
  std::vector<double> returns;      // per agent: the episode's return so far
  std::vector<std::uint8_t> done, active;  // per agent: terminated; took part in the last step
  bool diverged = false, needs_reset = false;
  std::vector<float> previous_action;
  std::vector<double> drawn;
  std::string ranges;               // JSON, the task's `randomize` schema
  std::vector<float> observation;
  std::vector<double> track;        // per agent, a task on a track: kTrackValues values (env.hpp)
};

std::string encodeSnapshot(const std::string& scenario_hash, const EnvSnapshot& s);
// Throws ExperimentError("snapshot", reason).
EnvSnapshot decodeSnapshot(const std::string& bytes, const std::string& scenario_hash);

// FNV-1a 64 (the checksum, and the scenario hash of task_context.cpp).
std::uint64_t fnv1a64(const void* data, std::size_t n, std::uint64_t h = 0xcbf29ce484222325ull);

}  // namespace groundsim::experiments
