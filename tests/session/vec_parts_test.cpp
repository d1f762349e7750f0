// The split of a vectorised reply into one-datagram parts and its
// reassembly (protocol/vec_parts.hpp): every part within the limit, the
// reassembled reply equal to the whole, missing parts named.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "protocol/limits.hpp"
#include "protocol/vec_parts.hpp"

namespace groundsim::net {
namespace {

using groundsim::vec_reply_t;

vec_reply_t whole(int envs, int obs, int snapshot_bytes = 0) {
  vec_reply_t w{};
  w.request_id = 42;
  w.client_id = "test";
  w.session_id = "0000ABCD";
  w.ok = true;
  w.nparts = 1;
  w.num_envs = envs;
  w.env_count = envs;
  w.obs_size = obs;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10, 10);
  for (int i = 0; i < envs * obs; ++i) w.obs.push_back(u(rng));
  w.nobs = envs * obs;
  for (int i = 0; i < envs; ++i) {
    w.rewards.push_back(u(rng));
    w.terminated.push_back(i % 3 == 0);
    w.truncated.push_back(i % 5 == 0);
    w.episode.push_back(i);
    w.episode_steps.push_back(2 * i);
    w.episode_return.push_back(u(rng));
    w.diverged.push_back(i % 7 == 0);
    w.active.push_back(i % 4 != 0);
  }
  for (int i = 0; i < snapshot_bytes; ++i) w.snapshot.push_back(static_cast<uint8_t>(rng()));
  w.snapshot_total = w.nsnapshot = snapshot_bytes;
  return w;
}

std::vector<std::uint8_t> encode(const vec_reply_t& m) {
  std::vector<std::uint8_t> b(m.getEncodedSize());
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

TEST(VecParts, ThousandEnvsSplitBelowTheLimitAndReassembleExactly) {
  const vec_reply_t w = whole(1024, 40);
  ASSERT_GT(static_cast<std::size_t>(w.getEncodedSize()), kMaxVecPartBytes);  // needs splitting
  std::vector<vec_reply_t> parts = splitVecReply(w);
  ASSERT_GT(parts.size(), 1u);
  for (const auto& p : parts) {
    EXPECT_LE(static_cast<std::size_t>(p.getEncodedSize()), kMaxVecPartBytes);
    EXPECT_EQ(p.nparts, static_cast<int>(parts.size()));
  }
  // arrival order must not matter
  std::reverse(parts.begin(), parts.end());
  VecAssembler a(42);
  for (const auto& p : parts) EXPECT_EQ(a.add(p), "");
  ASSERT_TRUE(a.complete());
  const vec_reply_t r = a.take();
  // equal to the whole, byte for byte on the wire (floats and doubles bit for bit)
  vec_reply_t expect = w;
  expect.part = 0;
  expect.nparts = 1;
  EXPECT_EQ(encode(r), encode(expect));
}

TEST(VecParts, SnapshotLargerThanAPartIsSplitAndJoined) {
  const vec_reply_t w = whole(0, 10, 150000);
  const std::vector<vec_reply_t> parts = splitVecReply(w);
  ASSERT_GE(parts.size(), 3u);
  VecAssembler a(42);
  for (const auto& p : parts) {
    EXPECT_LE(static_cast<std::size_t>(p.getEncodedSize()), kMaxVecPartBytes);
    EXPECT_EQ(a.add(p), "");
  }
  ASSERT_TRUE(a.complete());
  EXPECT_EQ(a.take().snapshot, w.snapshot);
}

TEST(VecParts, ASmallReplyIsOnePart) {
  const std::vector<vec_reply_t> parts = splitVecReply(whole(4, 10));
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].part, 0);
  EXPECT_EQ(parts[0].nparts, 1);
  EXPECT_EQ(parts[0].env_count, 4);
}

TEST(VecParts, MissingPartsAreNamed) {
  const std::vector<vec_reply_t> parts = splitVecReply(whole(1024, 40));
  ASSERT_GE(parts.size(), 4u);
  VecAssembler a(42);
  EXPECT_EQ(a.missingText(), "every part (none arrived)");
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (i != 1 && i != 3) a.add(parts[i]);
  EXPECT_FALSE(a.complete());
  EXPECT_EQ(a.missing(), (std::vector<int>{1, 3}));
  EXPECT_EQ(a.missingText(), "parts 1, 3 of " + std::to_string(parts.size()));
}

TEST(VecParts, ContradictingPartsAreRefusedNotMerged) {
  std::vector<vec_reply_t> parts = splitVecReply(whole(1024, 40));
  VecAssembler a(42);
  ASSERT_EQ(a.add(parts[0]), "");
  EXPECT_NE(a.add(parts[0]), "");  // twice
  vec_reply_t other = parts[1];
  other.nparts += 1;
  EXPECT_NE(a.add(other), "");
  vec_reply_t outside = parts[1];
  outside.env_begin = 1020;  // runs past num_envs
  EXPECT_NE(a.add(outside), "");
  vec_reply_t shape = parts[1];
  shape.obs_size = 39;
  EXPECT_NE(a.add(shape), "");
  EXPECT_EQ(a.missing().size(), parts.size() - 1);
}

}  // namespace
}  // namespace groundsim::net
