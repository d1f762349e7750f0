// The session service in process: requests in, replies and events out
// through a recording output (the worker pool is real; waits are bounded
// and never part of a verdict).
#include <gtest/gtest.h>

#include <thread>

#include "fakes.hpp"
#include "session/service.hpp"

namespace groundsim::session::test {
namespace {

Request create(std::int64_t id, double rate = 0, double publish_rate = 0) {
  Request r;
  r.op = Op::Create;
  r.request_id = id;
  r.client_id = "c";
  r.scenario_json = carScenario();
  r.rate = rate;
  r.publish_rate = publish_rate;
  r.duration = -1;
  return r;
}

TEST(Service, ExtremeRatesAreRefusedNamingTheField) {
  RecordingOutput out;
  SessionService service(ServiceConfig{}, out);
  service.handleRequest(create(1, 1e-12));
  service.handleRequest(create(2, 0, 1e-300));
  service.handleRequest(create(3, -1));
  Reply r;
  ASSERT_TRUE(out.waitReply(1, &r));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.code, ErrorCode::BadRequest);
  EXPECT_EQ(r.error.rfind("rate: 1e-12 is outside [0.001, 1000]", 0), 0u) << r.error;
  ASSERT_TRUE(out.waitReply(2, &r));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.error.rfind("publish_rate: 1e-300 is outside", 0), 0u) << r.error;
  ASSERT_TRUE(out.waitReply(3, &r));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(service.status().sessions.size(), 0u);
}

TEST(Service, AStoppedSessionStaysInTheHeartbeatWithItsLastSeq) {
  RecordingOutput out;
  SessionService service(ServiceConfig{}, out);
  service.handleRequest(create(1));
  Reply created;
  ASSERT_TRUE(out.waitReply(1, &created));
  ASSERT_TRUE(created.ok) << created.error;
  Request stop;
  stop.op = Op::Stop;
  stop.request_id = 2;
  stop.client_id = "c";
  stop.session_id = created.session_id;
  stop.token = created.token;
  service.handleRequest(stop);
  Reply stopped;
  ASSERT_TRUE(out.waitReply(2, &stopped));
  ASSERT_TRUE(stopped.ok);
  const ServiceStatus st = service.status();
  EXPECT_TRUE(st.sessions.empty()) << "a stopped session is unknown to requests";
  ASSERT_EQ(st.ended.size(), 1u);
  EXPECT_EQ(st.ended[0].session_id, created.session_id);
  EXPECT_EQ(st.ended[0].status, Status::Stopped);
  EXPECT_GE(st.ended[0].seq, 0);
}

TEST(Service, AnInvalidScenarioIsAnswered) {
  RecordingOutput out;
  SessionService service(ServiceConfig{}, out);
  Request r = create(5);
  r.scenario_json = R"({"ground": {"type": "plane"}, "vehicle": {}, "duration": -1})";
  service.handleRequest(r);
  Reply reply;
  ASSERT_TRUE(out.waitReply(5, &reply));
  EXPECT_FALSE(reply.ok);
  EXPECT_EQ(reply.code, ErrorCode::BadScenario);
  EXPECT_EQ(out.eventsWith(ErrorCode::BadScenario), 1);
}

}  // namespace
}  // namespace groundsim::session::test

namespace groundsim::session::test {
namespace {

// One client cannot take the server (docs/reliability.md, Fairness): a
// client that creates in a loop is refused at --client-sessions, naming the
// limit and the flag, while another client still creates; the processes of
// one principal (the id up to '/') count as one client; the create rate
// refills with time (a manual clock: no wall-clock verdict).
TEST(Service, OneClientIsBoundedWhileAnotherStillCreates) {
  RecordingOutput out;
  ManualClock clock;
  ServiceConfig cfg;
  cfg.max_sessions = 8;
  cfg.max_client_sessions = 3;
  cfg.client_creates_per_minute = 6;  // a burst of 6, then one every 10 s
  SessionService service(cfg, out, clock);
  auto createAs = [&](std::int64_t id, const std::string& client) {
    Request r = create(id);
    r.client_id = client;
    service.handleRequest(r);
    Reply reply;
    EXPECT_TRUE(out.waitReply(id, &reply)) << id;
    return reply;
  };
  std::vector<Reply> made;
  // two processes of one principal ("cli-loop/1", "cli-loop/2") are one client
  for (int k = 1; k <= 3; ++k) {
    made.push_back(createAs(k, "cli-loop/" + std::to_string(k % 2)));
    ASSERT_TRUE(made.back().ok) << made.back().error;
  }
  const Reply fourth = createAs(4, "cli-loop/9");
  EXPECT_FALSE(fourth.ok);
  EXPECT_EQ(fourth.code, ErrorCode::TooManySessions);
  EXPECT_NE(fourth.error.find("too many sessions for client 'cli-loop': it holds 3, at most 3 (server --client-sessions"),
            std::string::npos)
      << fourth.error;
  const Reply other = createAs(5, "cli-other/1");
  EXPECT_TRUE(other.ok) << "another client still creates: " << other.error;
  auto stopAs = [&](std::int64_t id, const Reply& made_by) {
    Request stop;
    stop.op = Op::Stop;
    stop.request_id = id;
    stop.client_id = "cli-loop/1";
    stop.session_id = made_by.session_id;
    stop.token = made_by.token;
    service.handleRequest(stop);
    Reply stopped;
    ASSERT_TRUE(out.waitReply(id, &stopped));
    ASSERT_TRUE(stopped.ok) << stopped.error;
  };
  // a stopped session frees its place; the rate bucket (6: 4 taken) allows two more now
  stopAs(6, made[0]);
  EXPECT_TRUE(createAs(7, "cli-loop/1").ok);
  stopAs(8, made[1]);
  const Reply early = createAs(9, "cli-loop/1");
  EXPECT_TRUE(early.ok) << early.error;  // the 6th create of the minute
  stopAs(10, made[2]);
  // the burst of 6 used up (the refused 4th took one): refused by rate, naming it
  const Reply fast = createAs(11, "cli-loop/1");
  EXPECT_FALSE(fast.ok);
  EXPECT_NE(fast.error.find("at most 6 a minute (server --client-creates)"), std::string::npos) << fast.error;
  clock.advance(10.5);  // one create's worth refilled
  EXPECT_TRUE(createAs(12, "cli-loop/1").ok);
}

}  // namespace
}  // namespace groundsim::session::test
