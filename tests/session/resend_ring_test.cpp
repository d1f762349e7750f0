// The server's resend ring (server/lcm/resend_ring.*): bounded per session
// in frames and bytes, whole frames, Gone for what fell out, a rate limit
// per client that refills with time, and the adapter answering resend_t on
// the client's own channel.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <groundsim/resend_t.hpp>
#include <groundsim/resent_t.hpp>

#include "lcm/resend_ring.hpp"

namespace groundsim::net {
namespace {

using Clock = ResendRing::Clock;

std::vector<std::uint8_t> bytes(int n, std::uint8_t v) { return std::vector<std::uint8_t>(n, v); }

void frame(ResendRing& r, const std::string& s, std::int64_t seq, int size = 100, Clock::time_point now = Clock::now(),
           bool sent = true) {
  const auto b = bytes(size, static_cast<std::uint8_t>(seq));
  r.addFrame(s, seq, "GROUNDSIM_STATE_" + s, b.data(), b.size(), sent, now);
  r.addFrame(s, seq, "GROUNDSIM_CONTACT_" + s, b.data(), b.size(), sent, now);
}

constexpr auto kOwner = ResendRing::Scope::Owner;
constexpr auto kPublished = ResendRing::Scope::Published;

TEST(ResendRing, AnswersWholeFramesInOrderAndGoneForWhatFellOut) {
  ResendLimits lim;
  lim.frames_per_session = 10;
  ResendRing r(lim);
  for (int s = 0; s < 100; ++s) frame(r, "a", s);
  // 10 frames of 2 messages are 20 messages; the ring keeps 30 messages
  const auto got = r.answer("c", "a", 80, 99);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.front().status, ResendRing::Status::Gone);
  EXPECT_EQ(got.front().seq, 80);
  const std::int64_t oldest = got.front().last_seq + 1;
  EXPECT_GE(oldest, 85);   // at least 10 frames kept...
  EXPECT_LE(oldest, 90);   // ...and at most 3 x 10 messages
  std::int64_t expect = oldest;
  for (std::size_t i = 1; i < got.size(); i += 2) {
    ASSERT_EQ(got[i].status, ResendRing::Status::Ok);
    EXPECT_EQ(got[i].seq, expect);
    EXPECT_EQ(got[i].channel, "GROUNDSIM_STATE_a");
    EXPECT_EQ(got[i + 1].seq, expect);
    EXPECT_EQ(got[i + 1].channel, "GROUNDSIM_CONTACT_a");
    EXPECT_EQ(got[i].bytes, bytes(100, static_cast<std::uint8_t>(expect)));
    ++expect;
  }
  EXPECT_EQ(expect, 100);
  // to = -1: up to the newest; beyond the newest: nothing more
  EXPECT_EQ(r.answer("c", "a", 99, -1).size(), 2u);
  EXPECT_TRUE(r.answer("c", "a", 100, 200).empty());
  EXPECT_EQ(r.answer("c", "nope", 0, 5).front().status, ResendRing::Status::UnknownSession);
}

TEST(ResendRing, BytesPerSessionBoundTheRing) {
  ResendLimits lim;
  lim.bytes_per_session = 10000;
  ResendRing r(lim);
  for (int s = 0; s < 1000; ++s) frame(r, "a", s, 1000);
  EXPECT_LE(r.stats().bytes_held, 10000u + 2000u);  // at most one frame over
  EXPECT_GE(r.stats().bytes_held, 8000u);
  // a frame larger than the budget alone is still kept (the newest)
  frame(r, "a", 1000, 50000);
  EXPECT_EQ(r.answer("c", "a", 1000, 1000).size(), 2u);
}

TEST(ResendRing, ARecorderOverItsRateIsToldToWaitAndServedLater) {
  ResendLimits lim;
  lim.messages_per_s = 100;
  lim.burst_s = 0.5;  // 50 messages at once
  ResendRing r(lim);
  const auto t0 = Clock::now();
  for (int s = 0; s < 1000; ++s) frame(r, "a", s, 100, t0);
  const auto first = r.answer("greedy", "a", 0, 999, kOwner, t0);
  ASSERT_EQ(first.back().status, ResendRing::Status::Limited);
  const std::size_t sent = first.size() - 1;
  EXPECT_LE(sent, 50u);
  EXPECT_EQ(sent % 2, 0u);  // whole frames
  EXPECT_EQ(first.back().seq, static_cast<std::int64_t>(sent / 2));
  EXPECT_EQ(first.back().last_seq, 999);
  // another client has its own bucket
  EXPECT_EQ(r.answer("other", "a", 0, 9, kOwner, t0).size(), 20u);
  // right away: nothing; a quarter second later: about 25 more messages
  EXPECT_EQ(r.answer("greedy", "a", 25, 999, kOwner, t0).front().status, ResendRing::Status::Limited);
  const auto later = r.answer("greedy", "a", 25, 999, kOwner, t0 + std::chrono::milliseconds(250));
  EXPECT_GE(later.size() - 1, 20u);
  EXPECT_LE(later.size() - 1, 26u);
}

TEST(ResendRing, SessionsAndClientsAreBoundedAndRingsExpire) {
  ResendLimits lim;
  lim.sessions = 4;
  lim.clients = 2;
  lim.linger_s = 10;
  ResendRing r(lim);
  const auto t0 = Clock::now();
  for (int k = 0; k < 10; ++k) frame(r, "s" + std::to_string(k), 0, 100, t0 + std::chrono::seconds(k));
  EXPECT_EQ(r.stats().sessions, 4);
  EXPECT_EQ(r.answer("c", "s0", 0, 0).front().status, ResendRing::Status::UnknownSession);
  EXPECT_EQ(r.answer("c", "s9", 0, 0).size(), 2u);
  for (int k = 0; k < 50; ++k) r.answer("client" + std::to_string(k), "s9", 0, 0);
  r.expire(t0 + std::chrono::seconds(15));  // s6..s9, written at 6..9 s, are within 10 s
  EXPECT_EQ(r.stats().sessions, 4);
  r.expire(t0 + std::chrono::milliseconds(16500));  // s6 is not
  EXPECT_EQ(r.stats().sessions, 3);
  r.expire(t0 + std::chrono::seconds(100));
  EXPECT_EQ(r.stats().sessions, 0);
}

TEST(ResendRing, EventsAreOneServerWideStream) {
  ResendLimits lim;
  lim.events = 100;
  ResendRing r(lim);
  for (int s = 0; s < 300; ++s) {
    const auto b = bytes(10, static_cast<std::uint8_t>(s));
    r.addEvent(s, "GROUNDSIM_EVENT", b.data(), b.size());
  }
  const auto got = r.answer("c", "", 150, 210);
  ASSERT_EQ(got.front().status, ResendRing::Status::Gone);
  EXPECT_EQ(got.front().last_seq, 199);
  EXPECT_EQ(got.size(), 1u + 11u);
  EXPECT_EQ(got.back().seq, 210);
}

// A fleet's server that published part of a session and then lost it (a
// takeover while it was fenced) answers only the messages it sent: not
// the frames it kept unsent while fenced (the new owner publishes its own
// under those seqs), no Gone for what fell out and no UnknownSession, which
// the owner says for the session.
TEST(ResendRing, APreviousOwnerAnswersOnlyWhatItSent) {
  ResendLimits lim;
  lim.frames_per_session = 10;
  ResendRing r(lim);
  const auto t0 = Clock::now();
  for (int s = 0; s < 30; ++s) frame(r, "a", s, 100, t0, /*sent=*/true);
  for (int s = 30; s < 33; ++s) frame(r, "a", s, 100, t0, /*sent=*/false);  // fenced: kept, not sent
  const auto owner = r.answer("c", "a", 0, -1, kOwner, t0);
  ASSERT_EQ(owner.front().status, ResendRing::Status::Gone);
  EXPECT_EQ(owner.back().seq, 32);  // the owner answers with what it kept too
  const auto before = r.answer("c", "a", 0, -1, kPublished, t0);
  ASSERT_FALSE(before.empty());
  for (const auto& m : before) {
    EXPECT_EQ(m.status, ResendRing::Status::Ok);
    EXPECT_LT(m.seq, 30);
  }
  EXPECT_EQ(before.back().seq, 29);
  EXPECT_EQ(before.size(), owner.size() - 1 - 2 * 3);  // less the Gone and the three kept frames
  EXPECT_TRUE(r.answer("c", "a", 30, 32, kPublished, t0).empty());
  EXPECT_TRUE(r.answer("c", "unknown", 0, 5, kPublished, t0).empty());
}

// A server that took a session over at seq 40 holds nothing before it:
// those seqs an earlier owner published (Elsewhere, ask it), and those of
// its own that fell out of its ring are Gone.
TEST(ResendRing, SeqsBeforeATakeoverAreElsewhere) {
  ResendLimits lim;
  lim.frames_per_session = 10;
  ResendRing r(lim);
  for (int s = 40; s < 100; ++s) frame(r, "a", s);
  const auto got = r.answer("c", "a", 30, 95);
  ASSERT_GE(got.size(), 3u);
  EXPECT_EQ(got[0].status, ResendRing::Status::Elsewhere);
  EXPECT_EQ(got[0].seq, 30);
  EXPECT_EQ(got[0].last_seq, 39);
  EXPECT_EQ(got[1].status, ResendRing::Status::Gone);
  EXPECT_EQ(got[1].seq, 40);
  EXPECT_EQ(got[2].status, ResendRing::Status::Ok);
  EXPECT_EQ(got[2].seq, got[1].last_seq + 1);
  // a session created here starts at seq 0: nothing is elsewhere
  frame(r, "b", 0);
  EXPECT_EQ(r.answer("c", "b", 0, 0).front().status, ResendRing::Status::Ok);
  // the previous owner's view of it: only what it holds, silent on the rest
  EXPECT_TRUE(r.answer("c", "a", 30, 39, kPublished).empty());
  EXPECT_EQ(r.stats().elsewhere, 1);
}

}  // namespace
}  // namespace groundsim::net
