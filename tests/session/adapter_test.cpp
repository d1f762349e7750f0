// The LCM adapter over LCM's in-process memq:// transport: raw datagrams in,
// wire replies and events out, without a network.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <groundsim/drive_t.hpp>
#include <groundsim/event_t.hpp>
#include <groundsim/reply_t.hpp>
#include <groundsim/request_t.hpp>
#include <groundsim/resend_t.hpp>
#include <groundsim/resent_t.hpp>

#include "fakes.hpp"
#include "lcm/lcm_server.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"

namespace groundsim::net {
namespace {

struct Ear {
  std::vector<groundsim::event_t> events;
  std::vector<groundsim::reply_t> replies;
  void onEvent(const lcm::ReceiveBuffer* b, const std::string&) {
    groundsim::event_t m;
    if (decodeMessage(b->data, static_cast<int>(b->data_size), m, "event_t").ok()) events.push_back(m);
  }
  void onReply(const lcm::ReceiveBuffer* b, const std::string&) {
    groundsim::reply_t m;
    if (decodeMessage(b->data, static_cast<int>(b->data_size), m, "reply_t").ok()) replies.push_back(m);
  }
};

class Adapter : public ::testing::Test {
 protected:
  Adapter() : server_("memq://", session::ServiceConfig{}, /*verbose=*/false) {
    server_.lcm().subscribe(kEventChannel, &Ear::onEvent, &ear_);
    server_.lcm().subscribe(kReplyChannel, &Ear::onReply, &ear_);
  }
  void send(const char* channel, const void* data, int size) {
    server_.lcm().publish(channel, data, size);
    while (server_.lcm().handleTimeout(10) > 0) {
    }
  }
  void send(const groundsim::request_t& r) {
    std::vector<std::uint8_t> buf(r.getEncodedSize());
    r.encode(buf.data(), 0, static_cast<int>(buf.size()));
    send(kRequestChannel, buf.data(), static_cast<int>(buf.size()));
  }

  LcmServer server_;
  Ear ear_;
};

TEST_F(Adapter, GarbageIsAnsweredWithAnEventNamingTheChannel) {
  const std::string junk(100, '\x7f');
  send(kRequestChannel, junk.data(), static_cast<int>(junk.size()));
  send(kDriveChannel, junk.data(), 3);
  ASSERT_EQ(ear_.events.size(), 2u);
  EXPECT_EQ(ear_.events[0].code, groundsim::event_t::ERR_FINGERPRINT);
  EXPECT_EQ(ear_.events[0].channel, kRequestChannel);
  EXPECT_EQ(ear_.events[1].code, groundsim::event_t::ERR_DECODE);
}

TEST_F(Adapter, HostileLengthsAreRefusedNotTrusted) {
  // found by fuzz/datagram_fuzz.cpp: lcm-gen's decoder took a string length
  // of INT32_MIN, computed len - 1 in int32 (INT32_MAX) and copied 2 GB past
  // the datagram; an array count is resized to before any check
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_LIST;
  r.client_id = "c";
  std::vector<std::uint8_t> buf(r.getEncodedSize());
  r.encode(buf.data(), 0, static_cast<int>(buf.size()));
  const std::size_t len_at = 8 + 3 * 8;  // hash, utime, seq, request_id, then client_id's length
  for (std::uint32_t bad : {0x80000000u, 0u, 0xffffffffu}) {
    for (int i = 0; i < 4; ++i) buf[len_at + i] = static_cast<std::uint8_t>(bad >> (24 - 8 * i));
    send(kRequestChannel, buf.data(), static_cast<int>(buf.size()));
  }
  groundsim::drive_t d{};
  d.nwheels = 100;
  d.drive_torque.assign(100, 0.0);
  d.brake_torque.assign(100, 0.0);
  d.steer.assign(100, 0.0);
  std::vector<std::uint8_t> dbuf(d.getEncodedSize());
  d.encode(dbuf.data(), 0, static_cast<int>(dbuf.size()));
  send(kDriveChannel, dbuf.data(), 8 + 16 + 3 * 5 + 4 + 1 + 16);  // cut: 100 wheels announced, 2 sent
  ASSERT_EQ(ear_.events.size(), 4u);
  for (const auto& e : ear_.events) EXPECT_EQ(e.code, groundsim::event_t::ERR_DECODE) << e.reason;
  EXPECT_TRUE(ear_.replies.empty());
}

TEST_F(Adapter, HugeOrControlCharacterIdsAreRefusedQuotedAndCut) {
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_LIST;
  r.request_id = 1;
  r.client_id = std::string(100000, 'x');
  send(r);
  ASSERT_EQ(ear_.events.size(), 1u);
  EXPECT_NE(ear_.events[0].reason.find("client_id"), std::string::npos);
  EXPECT_LT(ear_.events[0].reason.size(), 400u) << "the id was echoed whole";
  EXPECT_TRUE(ear_.replies.empty()) << "no reply to a client id nobody can have";

  r.client_id = "c";
  r.session_id = "AB\x1b[2J";  // (LCM strings end at a NUL: it never arrives)
  r.op = groundsim::request_t::OP_STOP;
  send(r);
  ASSERT_EQ(ear_.replies.size(), 1u);
  EXPECT_FALSE(ear_.replies[0].ok);
  EXPECT_NE(ear_.replies[0].error.find("session_id: \"AB\\x1b[2J\""), std::string::npos)
      << ear_.replies[0].error;
}

TEST_F(Adapter, ExtremeRateIsRefusedOnTheWire) {
  groundsim::request_t r{};
  r.op = groundsim::request_t::OP_CREATE;
  r.request_id = 9;
  r.client_id = "c";
  r.scenario_json = session::test::carScenario();
  r.rate = 1e-12;
  send(r);
  ASSERT_EQ(ear_.replies.size(), 1u);
  EXPECT_FALSE(ear_.replies[0].ok);
  EXPECT_EQ(ear_.replies[0].error_code, groundsim::event_t::ERR_BAD_REQUEST);
  EXPECT_NE(ear_.replies[0].error.find("rate: 1e-12"), std::string::npos) << ear_.replies[0].error;
}

}  // namespace
}  // namespace groundsim::net

namespace groundsim::net {
namespace {

struct ResentEar {
  std::vector<groundsim::resent_t> got;
  void on(const lcm::ReceiveBuffer* b, const std::string&) {
    groundsim::resent_t m;
    if (decodeMessage(b->data, static_cast<int>(b->data_size), m, "resent_t").ok()) got.push_back(m);
  }
};

// A recorder's re-requests: bad ones refused with an event naming the
// field; an unknown session answered on the recorder's own channel; events
// the server published resent as they were.
TEST_F(Adapter, ResendRequestsAreValidatedAndAnsweredOnTheRecordersChannel) {
  ResentEar resent;
  server_.lcm().subscribe(std::string(kResentPrefix) + "rec", &ResentEar::on, &resent);
  const auto sendResend = [&](const groundsim::resend_t& r) {
    std::vector<std::uint8_t> buf(r.getEncodedSize());
    r.encode(buf.data(), 0, static_cast<int>(buf.size()));
    send(kResendChannel, buf.data(), static_cast<int>(buf.size()));
  };
  groundsim::resend_t r{};
  r.client_id = "rec";
  r.stream = groundsim::resend_t::STREAM_SESSION;
  r.session_id = "NOPE";
  r.from_seq = -5;
  r.to_seq = 10;
  sendResend(r);
  ASSERT_FALSE(ear_.events.empty());
  EXPECT_NE(ear_.events.back().reason.find("from_seq"), std::string::npos) << ear_.events.back().reason;
  EXPECT_EQ(ear_.events.back().channel, kResendChannel);
  r.from_seq = 0;
  r.stream = 9;
  sendResend(r);
  EXPECT_NE(ear_.events.back().reason.find("stream"), std::string::npos) << ear_.events.back().reason;
  r.stream = groundsim::resend_t::STREAM_SESSION;
  r.client_id = "";
  sendResend(r);
  EXPECT_NE(ear_.events.back().reason.find("client_id"), std::string::npos) << ear_.events.back().reason;
  EXPECT_TRUE(resent.got.empty());
  // well formed, unknown session: answered, not an error
  r.client_id = "rec";
  sendResend(r);
  ASSERT_EQ(resent.got.size(), 1u);
  EXPECT_EQ(resent.got[0].status, +groundsim::resent_t::STATUS_UNKNOWN_SESSION);
  EXPECT_EQ(resent.got[0].session_id, "NOPE");
  // the refusals above were events 0..2: they come back byte for byte
  const std::size_t events_before = ear_.events.size();
  r.stream = groundsim::resend_t::STREAM_EVENTS;
  r.session_id = "";
  r.from_seq = 0;
  r.to_seq = -1;
  sendResend(r);
  ASSERT_GE(resent.got.size(), 4u);
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_EQ(resent.got[i].status, +groundsim::resent_t::STATUS_OK);
    EXPECT_EQ(resent.got[i].channel, kEventChannel);
    groundsim::event_t e;
    ASSERT_TRUE(decodeMessage(resent.got[i].data.data(), resent.got[i].size, e, "event_t").ok());
    EXPECT_EQ(e.seq, ear_.events[i - 1].seq);
    EXPECT_EQ(e.reason, ear_.events[i - 1].reason);
  }
  EXPECT_EQ(ear_.events.size(), events_before);  // a good request raises no event
}

}  // namespace
}  // namespace groundsim::net
