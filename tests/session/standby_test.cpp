// A fleet's standby (docs/fleet.md): the applied-command log it keeps of
// another server's session (gaps found and asked for again, the replay
// ending at the first one), the head of a state read without decoding it,
// and a resumption that takes no command at a tick the lost owner had
// already published.
#include <gtest/gtest.h>

#include <memory>

#include "fakes.hpp"
#include "lcm/convert.hpp"
#include "lcm/standby_log.hpp"
#include "session/session.hpp"

namespace groundsim::session::test {
namespace {

Applied entryAt(std::int64_t seq, std::int64_t frame, std::int64_t tick = 0) {
  Applied a;
  a.session_id = "00C0FFEE";
  a.seq = seq;
  a.frame_seq = frame;
  a.tick = tick;
  a.kind = AppliedKind::Drive;
  return a;
}

TEST(StandbyLog, GapsNameTheFramesAroundThem) {
  net::StandbyLog log;
  log.rebase(10, 100);  // a snapshot after 10 entries, at frame 100
  for (std::int64_t seq : {10, 11, 14, 15, 18}) log.add(entryAt(seq, 100 + 3 * (seq - 10)));
  log.add(entryAt(4, 40));  // in the snapshot already: dropped
  EXPECT_EQ(log.size(), 5u);
  const auto gaps = log.gaps();
  ASSERT_EQ(gaps.size(), 2u);
  EXPECT_EQ(gaps[0].first_seq, 12);
  EXPECT_EQ(gaps[0].last_seq, 13);
  EXPECT_EQ(gaps[0].from_frame, 103);  // entry 11's frame
  EXPECT_EQ(gaps[0].to_frame, 112);    // entry 14's
  EXPECT_EQ(gaps[1].first_seq, 16);
  EXPECT_EQ(gaps[1].last_seq, 17);
  // the replay stops at the first gap: entries 10 and 11
  const auto r = log.replayable();
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r.back().seq, 11);
  // the gap repaired, the replay goes on to the next
  log.add(entryAt(12, 106));
  log.add(entryAt(13, 109));
  EXPECT_EQ(log.replayable().size(), 6u);
  EXPECT_EQ(log.gaps().size(), 1u);
}

TEST(StandbyLog, AGapBeforeTheFirstEntryHeardStartsAtTheSnapshotsFrame) {
  net::StandbyLog log;
  log.rebase(5, 50);
  log.add(entryAt(7, 58));
  const auto gaps = log.gaps();
  ASSERT_EQ(gaps.size(), 1u);
  EXPECT_EQ(gaps[0].first_seq, 5);
  EXPECT_EQ(gaps[0].from_frame, 50);
  EXPECT_EQ(gaps[0].to_frame, 58);
  EXPECT_TRUE(log.replayable().empty());
}

TEST(StandbyLog, ANewOwnersLogIsKnownFromItsFirstSnapshot) {
  net::StandbyLog log;
  for (std::int64_t seq = 0; seq < 5; ++seq) log.add(entryAt(seq, seq));
  log.restart();  // a takeover elsewhere: where the new owner resumed is not known
  log.add(entryAt(9, 30));
  EXPECT_TRUE(log.gaps().empty()) << "no gap is claimed before the new owner's snapshot";
  EXPECT_TRUE(log.replayable().empty());
  log.rebase(9, 29);
  ASSERT_EQ(log.replayable().size(), 1u);
  EXPECT_EQ(log.replayable()[0].seq, 9);
}

TEST(StandbyLog, IsBounded) {
  net::StandbyLog log(8);
  for (std::int64_t seq = 0; seq < 100; ++seq) log.add(entryAt(seq, seq));
  EXPECT_EQ(log.size(), 8u);
}

TEST(PeekState, ReadsSeqTickAndEpochOfAnEncodedState) {
  Frame f;
  f.session_id = "00C0FFEE";
  f.seq = 1234;
  f.tick = 98765;
  f.t = 4.9;
  f.epoch = 3;
  f.reason = "a reason of some length";
  f.vehicles.resize(2);  // the epoch comes after the vehicles
  f.vehicles[0].wheel_count = 4;
  f.vehicles[1].wheel_count = 4;
  const groundsim::state_t m = net::toMessage(f);
  std::vector<std::uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  ASSERT_GT(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
  const auto h = net::peekState(bytes.data(), static_cast<int>(bytes.size()));
  ASSERT_TRUE(h);
  EXPECT_EQ(h->seq, 1234);
  EXPECT_EQ(h->tick, 98765);
  EXPECT_EQ(h->epoch, 3);
  // truncated, or another type: nothing
  EXPECT_FALSE(net::peekState(bytes.data(), 30));
  bytes[0] ^= 0xff;
  EXPECT_FALSE(net::peekState(bytes.data(), static_cast<int>(bytes.size())));
}

// The lost owner stepped on after its last applied entry and published those
// states; its standby resumes from an older snapshot. A command taken after
// the takeover must take effect after the owner's last published state, or
// the states published from there would differ from the owner's (issue 20's
// driven failover test caught it: the new owner applied a control at the
// tick of the last replayed entry, 5 ticks before the owner's last state).
TEST(SessionResume, TakesNoCommandBeforeTheOwnersLastPublishedState) {
  ServiceConfig cfg;
  cfg.slice = 0.002;
  cfg.replica_interval = 0.02;  // 400 ticks: a snapshot with every 50 Hz frame
  const scenario::Scene scene = carScene();
  SessionSetup setup;
  setup.id = "00C0FFEE";
  setup.token = "t";
  setup.name = "s1";
  setup.vehicle_names = {"car"};
  setup.duration = -1;
  setup.mode = Mode::Realtime;
  setup.rate = 1.0;
  setup.publish_rate = 50.0;
  ManualClock clock;
  RecordingOutput owner_out, standby_out;
  auto owner = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, owner_out, clock.now(), clock);
  const auto drive = [&](double torque) {
    Drive d;
    d.vehicle = 0;
    d.wheels.assign(4, WheelControl{});
    for (auto& w : d.wheels) w.drive_torque = torque;
    d.received = clock.now();
    return d;
  };
  owner->run(clock.now());
  owner->post(drive(50.0));
  for (int i = 0; i < 5; ++i) {  // 0.1 s: frames 1-5, ticks 400-2000
    clock.advance(0.02);
    owner->run(clock.now());
  }
  // the snapshot at tick 800 and the entries after it; the owner's last state
  const Replica* snap = nullptr;
  for (const Replica& r : owner_out.replicas)
    if (r.kind == Replica::Kind::Snapshot && r.tick == 800) snap = &r;
  ASSERT_NE(snap, nullptr);
  std::vector<Applied> log;
  for (const Applied& a : owner_out.applied)
    if (a.seq >= snap->applied_seq) log.push_back(a);
  const Frame last = owner_out.frames.back();
  ASSERT_EQ(last.tick, 2000);

  auto standby = std::make_shared<Session>(setup, scene.built.model, scene.built.initial, cfg, standby_out, clock.now(),
                                           clock);
  standby->setEpoch(2);
  ASSERT_EQ(standby->resume(*snap, log, last.tick), "");
  // a command that arrives at once, and the owner's own next step with it
  const Drive d = drive(-80.0);
  standby->post(d);
  owner->post(d);
  standby->run(clock.now());
  owner->run(clock.now());
  ASSERT_FALSE(standby_out.applied.empty());
  const Applied& taken = standby_out.applied.front();
  EXPECT_GE(taken.tick, last.tick) << "a command took effect before the owner's last published state";
  EXPECT_EQ(taken.frame_seq, last.seq + 1);
  // the frames after the snapshot were published again at the resumption,
  // each equal to the owner's (ticks 1200, 1600, 2000), and none after
  ASSERT_EQ(standby_out.frames.size(), 3u);
  for (const Frame& f : standby_out.frames) {
    const Frame& first = owner_out.frames.at(static_cast<size_t>(f.seq));
    EXPECT_EQ(f.tick, first.tick);
    EXPECT_EQ(f.energy, first.energy);
    EXPECT_EQ(f.vehicles.at(0).position, first.vehicles.at(0).position);
  }
  EXPECT_EQ(standby_out.frames.back().seq, last.seq);
  // the states after it are the owner's, the command applied alike
  for (int i = 0; i < 3; ++i) {
    clock.advance(0.02);
    owner->run(clock.now());
    standby->run(clock.now());
  }
  ASSERT_EQ(standby_out.frames.size(), 6u);
  EXPECT_EQ(standby_out.frames[3].seq, last.seq + 1);
  const Frame& o = owner_out.frames.back();
  const Frame& s = standby_out.frames.back();
  EXPECT_EQ(s.seq, o.seq);
  EXPECT_EQ(s.tick, o.tick);
  EXPECT_EQ(s.energy, o.energy);
  ASSERT_EQ(s.vehicles.size(), o.vehicles.size());
  EXPECT_EQ(s.vehicles[0].position, o.vehicles[0].position);
  EXPECT_EQ(s.vehicles[0].velocity, o.vehicles[0].velocity);
}

}  // namespace
}  // namespace groundsim::session::test
