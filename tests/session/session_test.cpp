// A Session stepped by hand: an injected clock and a recording output, no
// worker pool, no sleeps. Each test drives run(now) the way a worker would.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fakes.hpp"
#include "session/session.hpp"

namespace groundsim::session::test {
namespace {

struct Rig {
  explicit Rig(Mode mode, double rate = 1.0, double publish_rate = 50.0, Clock::duration tick = {})
      : clock(tick) {
    cfg.slice = 0.002;
    scenario::Scene scene = carScene();
    SessionSetup setup;
    setup.id = "00C0FFEE";
    setup.token = "t";
    setup.name = "s1";
    setup.vehicle_names = {"car"};
    setup.duration = -1;  // unlimited
    setup.mode = mode;
    setup.rate = rate;
    setup.publish_rate = publish_rate;
    session = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, out, clock.now(), clock);
  }
  std::optional<TimePoint> run() { return session->run(clock.now()); }
  Request request(Op op, std::int64_t id, std::int64_t steps = 0) {
    Request r;
    r.op = op;
    r.request_id = id;
    r.client_id = "c";
    r.session_id = "00C0FFEE";
    r.steps = steps;
    return r;
  }
  const Reply* reply(std::int64_t id) const {
    for (const auto& r : out.replies)
      if (r.request_id == id) return &r;
    return nullptr;
  }

  ServiceConfig cfg;
  ManualClock clock;
  RecordingOutput out;
  std::shared_ptr<Session> session;
};

constexpr double kDt = 5e-5;  // carScene()'s

TEST(Session, RealtimePublishesOnTheInjectedClock) {
  Rig rig(Mode::Realtime);
  const auto due = rig.run();  // the initial state
  ASSERT_EQ(rig.out.frames.size(), 1u);
  EXPECT_EQ(rig.out.frames[0].seq, 0);
  ASSERT_TRUE(due);
  // the next frame is due 1/50 s of wall time later, on the injected clock
  EXPECT_NEAR(seconds(*due - kEpoch), 0.02, 1e-9);
  rig.clock.set(*due);
  rig.run();
  ASSERT_EQ(rig.out.frames.size(), 2u);
  EXPECT_EQ(rig.out.frames[1].seq, 1);
  EXPECT_EQ(rig.out.frames[1].tick, 400);
  EXPECT_NEAR(rig.out.frames[1].t, 400 * kDt, 1e-12);
}

TEST(Session, RealtimeAtTwiceTheRateSimulatesTwiceAsFar) {
  Rig rig(Mode::Realtime, 2.0);
  rig.run();
  rig.clock.advance(0.1);  // 0.1 s of wall time: 0.2 s of simulation
  rig.run();
  EXPECT_EQ(rig.session->info(rig.clock.now()).tick, 4000);
}

TEST(Session, ExtremeRateSleepsInsteadOfSpinning) {
  // 1e-12 s of simulation per wall second: the next frame is 2e10 s away.
  // Converted to int64 nanoseconds that overflowed into the past, and the
  // session asked to run again at once, forever.
  Rig rig(Mode::Realtime, 1e-12);
  const auto due = rig.run();
  ASSERT_TRUE(due);
  EXPECT_GE(seconds(*due - kEpoch), 1e8) << "due time wrapped";
  rig.clock.advance(1.0);
  const auto again = rig.run();
  ASSERT_TRUE(again);
  EXPECT_GT(*again, rig.clock.now());
  EXPECT_EQ(rig.session->info(rig.clock.now()).tick, 0);
}

TEST(Session, CommandTimeoutReleasesTheTorque) {
  Rig rig(Mode::Realtime);
  rig.run();
  Drive d;
  d.vehicle = 0;
  d.wheels.assign(4, WheelControl{});
  for (auto& w : d.wheels) w.drive_torque = 1.0;
  d.received = rig.clock.now();
  rig.session->post(d);
  rig.clock.advance(0.4);  // within the 0.5 s timeout
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 0);
  rig.clock.advance(0.2);  // 0.6 s after the command
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 1);
  rig.clock.advance(0.2);
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::CommandTimeout), 1) << "one warning per expiry";
}

// The latency trace (server/lcm/latency_trace.hpp) follows a press through
// these two stamps: which drive a frame is the first to reflect, and when
// the session applied it.
TEST(Session, FramesCarryWhenTheirLastDriveWasReceivedAndApplied) {
  Rig rig(Mode::Realtime);
  const auto due = rig.run();
  ASSERT_EQ(rig.out.frames.size(), 1u);
  EXPECT_EQ(rig.out.frames[0].drive_received, TimePoint{}) << "no drive yet";
  Drive d;
  d.vehicle = 0;
  d.wheels.assign(4, WheelControl{});
  d.received = rig.clock.now();
  rig.clock.advance(0.003);  // the worker takes it 3 ms later
  const TimePoint applied = rig.clock.now();
  rig.session->post(d);
  rig.run();
  ASSERT_TRUE(due);
  rig.clock.set(*due);
  rig.run();
  ASSERT_EQ(rig.out.frames.size(), 2u);
  EXPECT_EQ(rig.out.frames[1].drive_received, d.received);
  EXPECT_EQ(rig.out.frames[1].drive_applied, applied);
}

TEST(Session, OverrunSkipsAheadWithOneWarning) {
  Rig rig(Mode::Realtime);
  rig.run();
  rig.clock.advance(3.0);  // the worker was away for 3 s: more than max_lag (0.5 s)
  rig.run();
  EXPECT_EQ(rig.out.eventsWith(ErrorCode::Overrun), 1);
  // the backlog is dropped, not raced through
  EXPECT_LT(rig.session->info(rig.clock.now()).tick, 2000);  // not 60,000
}

TEST(Session, LockstepResetInterruptsStepsAndRestoresTheInitialState) {
  // every clock read moves 1 ms: a 2 ms slice ends after a few steps
  Rig rig(Mode::Lockstep, 1.0, 50.0, std::chrono::milliseconds(1));
  rig.session->post(rig.request(Op::Step, 1, 1'000'000));
  rig.run();
  EXPECT_EQ(rig.reply(1), nullptr) << "a million steps do not fit one slice";
  rig.session->post(rig.request(Op::Reset, 2));
  rig.run();
  ASSERT_NE(rig.reply(1), nullptr);
  EXPECT_FALSE(rig.reply(1)->ok);
  EXPECT_NE(rig.reply(1)->error.find("reset"), std::string::npos);
  ASSERT_NE(rig.reply(2), nullptr);
  EXPECT_TRUE(rig.reply(2)->ok);
  rig.session->post(rig.request(Op::Step, 3, 3));
  for (int i = 0; i < 10 && !rig.reply(3); ++i) rig.run();
  ASSERT_NE(rig.reply(3), nullptr);
  ASSERT_TRUE(rig.reply(3)->state);
  EXPECT_EQ(rig.reply(3)->state->tick, 3);
  EXPECT_DOUBLE_EQ(rig.reply(3)->state->t, 3 * kDt);
}

TEST(Session, FailingOutputEndsTheSessionAndAnswersPendingSteps) {
  Rig rig(Mode::Lockstep);
  rig.out.throw_on_state = true;  // publishing the step's state throws, and so does the error path's final frame
  rig.session->post(rig.request(Op::Step, 7, 5));
  EXPECT_NO_THROW(rig.run());
  ASSERT_NE(rig.reply(7), nullptr) << "the step request was left unanswered";
  EXPECT_FALSE(rig.reply(7)->ok);
  EXPECT_EQ(rig.reply(7)->code, ErrorCode::Internal);
  EXPECT_GE(rig.out.eventsWith(ErrorCode::Internal), 1);
  EXPECT_EQ(rig.session->info(rig.clock.now()).status, Status::Diverged);
  // still answering afterwards
  rig.out.throw_on_state = false;
  rig.session->post(rig.request(Op::Step, 8, 1));
  rig.run();
  ASSERT_NE(rig.reply(8), nullptr);
  EXPECT_EQ(rig.reply(8)->code, ErrorCode::Diverged);
}

TEST(Pacing, ConversionsSaturate) {
  EXPECT_GT(toDuration(2e10), Clock::duration::zero());
  EXPECT_LT(toDuration(-2e10), Clock::duration::zero());
  EXPECT_EQ(toDuration(std::nan("")), Clock::duration::zero());
  // 1/(1e-300 Hz * 1e-3 s) is no step count: capped, never wrapped to 1
  EXPECT_EQ(stepsPerFrame(1e-300, 1e-3), 1'000'000'000'000'000);
  EXPECT_EQ(stepsPerFrame(50, 1e-3), 20);
  EXPECT_EQ(stepsPerFrame(1e300, 1e-3), 1);
  RealtimeAnchor a;
  a.reset(kEpoch, 0.0, 1e-12);
  EXPECT_GT(a.wallAt(0.02), kEpoch);
}

}  // namespace
}  // namespace groundsim::session::test
