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
