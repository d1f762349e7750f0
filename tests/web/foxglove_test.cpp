// The Foxglove endpoint's parts without sockets: the subprotocol choice,
// the client messages refused with the field named, the data frame's
// header, the channel registry (sessions come from heartbeats and the bus,
// go when quiet) and the feed (decodes only what some client wants).
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <groundsim/state_t.hpp>

#include "bridge/foxglove_channels.hpp"
#include "bridge/foxglove_feed.hpp"
#include "bridge/foxglove_protocol.hpp"

using namespace groundsim::web::foxglove;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

std::string errorOf(const std::string& text) {
  const auto m = parseClientMessage(text);
  const auto* e = std::get_if<ClientError>(&m);
  return e ? e->text() : "";
}

}  // namespace

TEST(Foxglove, SubprotocolPrefersTheSdksAndRefusesOthers) {
  EXPECT_EQ(chooseSubprotocol({"foxglove.sdk.v1"}), "foxglove.sdk.v1");
  EXPECT_EQ(chooseSubprotocol({"foxglove.websocket.v1"}), "foxglove.websocket.v1");
  EXPECT_EQ(chooseSubprotocol({"foxglove.websocket.v1, foxglove.sdk.v1"}), "foxglove.sdk.v1");
  EXPECT_EQ(chooseSubprotocol({"x", " foxglove.websocket.v1 "}), "foxglove.websocket.v1");
  EXPECT_FALSE(chooseSubprotocol({}));
  EXPECT_FALSE(chooseSubprotocol({"foxglove.sdk.v2, foxglove.websocket"}));
}

TEST(Foxglove, ClientMessagesParsedOrRefusedNamingTheField) {
  const auto sub = parseClientMessage(R"({"op":"subscribe","subscriptions":[{"id":3,"channelId":7},{"id":4.0,"channelId":8}]})");
  ASSERT_TRUE(std::holds_alternative<Subscribe>(sub));
  const auto& s = std::get<Subscribe>(sub).subscriptions;
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].id, 4u);
  EXPECT_EQ(s[1].channel, 8u);
  const auto un = parseClientMessage(R"({"op":"unsubscribe","subscriptionIds":[3]})");
  ASSERT_TRUE(std::holds_alternative<Unsubscribe>(un));

  EXPECT_NE(errorOf("{\"op\":").find("malformed JSON"), std::string::npos);
  EXPECT_NE(errorOf("7").find("must be a JSON object"), std::string::npos);
  EXPECT_NE(errorOf("{}").find("/op: missing"), std::string::npos);
  EXPECT_NE(errorOf(R"({"op":"fly"})").find("/op: unknown op \"fly\""), std::string::npos);
  EXPECT_NE(errorOf(R"({"op":"advertise","channels":[]})").find("clientPublish"), std::string::npos);
  EXPECT_NE(errorOf(R"({"op":"subscribe","subscriptions":[{"id":1}]})").find("/subscriptions/0/channelId: missing"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})").find("/subscriptions/0/id"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"op":"unsubscribe","subscriptionIds":[1,-2]})").find("/subscriptionIds/1"),
            std::string::npos);
  // a refusal quotes at most a short piece of what it got
  EXPECT_LT(errorOf(R"({"op":")" + std::string(10000, 'a') + "\"}").size(), 200u);
}

TEST(Foxglove, DataHeaderIsLittleEndian) {
  const auto h = dataHeader(0x01020304u, 0x1112131415161718ull);
  const std::vector<std::uint8_t> expect = {1, 4, 3, 2, 1, 0x18, 0x17, 0x16, 0x15, 0x14, 0x13, 0x12, 0x11};
  EXPECT_EQ(std::vector<std::uint8_t>(h.begin(), h.end()), expect);
}

TEST(Foxglove, ChannelsComeWithSessionsAndGoWhenQuiet) {
  ChannelRegistry r;
  const auto t0 = Clock::now();
  ASSERT_EQ(r.size(), 1u);  // /events
  EXPECT_EQ(r.find(1)->topic, "/events");
  auto c = r.listed({"AAAAAAAA"}, t0);
  ASSERT_EQ(c.added.size(), 3u);  // state, events, applied
  EXPECT_EQ(c.added[0]->topic, "/AAAAAAAA/state");
  EXPECT_EQ(c.added[0]->schema_name, "groundsim.state");
  EXPECT_TRUE(json::parse(c.added[0]->schema).contains("properties"));
  EXPECT_TRUE(r.listed({"AAAAAAAA"}, t0).empty());  // listed again: nothing new
  // a road car's stream once heard; an event naming an unknown session makes none
  c = r.heard("AAAAAAAA", Stream::CarState, t0);
  ASSERT_EQ(c.added.size(), 1u);
  EXPECT_EQ(c.added[0]->topic, "/AAAAAAAA/car_state");
  EXPECT_TRUE(r.heard("BBBBBBBB", Stream::Events, t0).empty());
  // a session heard on the bus without a heartbeat (a replay)
  EXPECT_EQ(r.heard("CCCCCCCC", Stream::State, t0).added.size(), 3u);
  // quiet for longer than kGoneAfter: gone, with every channel
  EXPECT_TRUE(r.expire(t0 + std::chrono::seconds(2)).empty());
  r.heard("CCCCCCCC", Stream::State, t0 + std::chrono::seconds(2));
  c = r.expire(t0 + std::chrono::seconds(4));
  EXPECT_EQ(c.removed.size(), 4u);
  EXPECT_FALSE(r.channelOf("AAAAAAAA", Stream::State));
  EXPECT_TRUE(r.channelOf("CCCCCCCC", Stream::State));
  EXPECT_EQ(r.size(), 4u);
  // ids are never reused
  const auto again = r.listed({"AAAAAAAA"}, t0 + std::chrono::seconds(4));
  EXPECT_GT(again.added[0]->id, 8u);
}

TEST(Foxglove, RegistryIsBounded) {
  ChannelRegistry r;
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < ChannelRegistry::kMaxSessions + 10; ++i) {
    char b[9];
    std::snprintf(b, sizeof b, "%08zX", i);
    ids.push_back(b);
  }
  r.listed(ids, Clock::now());
  EXPECT_EQ(r.sessions(), ChannelRegistry::kMaxSessions);
}

TEST(Foxglove, FeedDecodesOnlyWhatIsWanted) {
  std::vector<std::string> heard, messages;
  Feed feed(nullptr, Feed::Hooks{{},
                                 [&](const std::string& s, Stream) { heard.push_back(s); },
                                 [&](const std::string& s, Stream, std::uint64_t ns, auto json) {
                                   EXPECT_GT(ns, 1600000000ull * 1000000000ull);  // the receive time, Unix epoch
                                   messages.push_back(*json);
                                   (void)s;
                                 },
                                 {}});
  groundsim::state_t m{};
  m.session_id = "ABCDEF01";
  m.seq = 5;
  m.t = 0.5;
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  feed.handle(b.data(), static_cast<int>(b.size()), "GROUNDSIM_STATE_ABCDEF01");
  EXPECT_EQ(heard.size(), 1u);
  EXPECT_TRUE(messages.empty());
  EXPECT_EQ(feed.decoded(), 0u);
  feed.setWanted({"GROUNDSIM_STATE_ABCDEF01"});
  feed.handle(b.data(), static_cast<int>(b.size()), "GROUNDSIM_STATE_ABCDEF01");
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_EQ(json::parse(messages[0])["seq"], 5);
  EXPECT_EQ(heard.size(), 1u);  // at most once a second per channel
  // not a session's channel: no topic is made of it
  feed.handle(b.data(), static_cast<int>(b.size()), "GROUNDSIM_STATE_../../x");
  EXPECT_EQ(heard.size(), 1u);
}
