// The bridge's side of contact between bodies: the scenario's objects in
// the layout a browser gets (placed as the scene builds them), and the
// contact channel's messages re-encoded for the browsers watching, with
// anything undecodable counted and dropped.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <groundsim/contact_state_t.hpp>
#include <groundsim/state_t.hpp>

#include "bridge/contact_feed.hpp"
#include "bridge/scene_view.hpp"

using namespace groundsim::web;
using nlohmann::json;

namespace {

template <class T>
std::vector<std::uint8_t> encoded(const T& m) {
  std::vector<std::uint8_t> b(static_cast<size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

groundsim::contact_state_t contactState(const std::string& session) {
  groundsim::contact_state_t m{};
  m.utime = 1500000;
  m.seq = 75;
  m.session_id = session;
  m.t = 1.5;
  groundsim::object_state_t o{};
  o.name = "cone1";
  const double p[3] = {20, 0.5, 0.35}, q[4] = {1, 0, 0, 0};
  for (int i = 0; i < 3; ++i) o.position[i] = p[i];
  for (int i = 0; i < 4; ++i) o.orientation[i] = q[i];
  m.objects.push_back(o);
  m.nobjects = 1;
  groundsim::hit_t h{};
  h.a = "sedan";
  h.b = "cone1";
  h.position[0] = 19.8;
  h.force[0] = -450;
  h.impulse = 12;
  h.peak_force = 900;
  h.closing_speed = 11.5;
  h.depth = 0.02;
  h.begin = 1.48;
  h.hard = true;
  m.hits.push_back(h);
  m.nhits = 1;
  return m;
}

struct Recorder {
  std::vector<std::pair<std::string, std::string>> delivered;
  std::vector<std::string> bad;
  ContactFeed::Hooks hooks(const std::string& watched) {
    return {[watched](const std::string& id) { return id == watched; },
            [this](const std::string& id, std::shared_ptr<const std::string> j) { delivered.emplace_back(id, *j); },
            [this](const std::string&, const std::string& reason) { bad.push_back(reason); }};
  }
};

}  // namespace

TEST(ContactFeed, WatchedSessionsGetTheirObjectsAndHits) {
  Recorder r;
  ContactFeed feed(nullptr, r.hooks("s1"));
  const auto bytes = encoded(contactState("s1"));
  feed.handle(bytes.data(), static_cast<int>(bytes.size()), "GROUNDSIM_CONTACT_s1");
  ASSERT_EQ(r.delivered.size(), 1u);
  EXPECT_EQ(r.delivered[0].first, "s1");
  const json j = json::parse(r.delivered[0].second);
  EXPECT_EQ(j["op"], "contact");
  EXPECT_EQ(j["seq"], 75);
  EXPECT_DOUBLE_EQ(j["t"].get<double>(), 1.5);
  ASSERT_EQ(j["objects"].size(), 1u);
  EXPECT_EQ(j["objects"][0]["name"], "cone1");
  EXPECT_DOUBLE_EQ(j["objects"][0]["p"][2].get<double>(), 0.35);
  EXPECT_EQ(j["objects"][0]["q"].size(), 4u);
  ASSERT_EQ(j["hits"].size(), 1u);
  const json& h = j["hits"][0];
  EXPECT_EQ(h["a"], "sedan");
  EXPECT_EQ(h["b"], "cone1");
  EXPECT_DOUBLE_EQ(h["F"][0].get<double>(), -450);
  EXPECT_DOUBLE_EQ(h["peak"].get<double>(), 900);
  EXPECT_DOUBLE_EQ(h["closing"].get<double>(), 11.5);
  EXPECT_EQ(h["hard"], true);

  // a session nobody watches costs the decode only
  const auto other = encoded(contactState("s2"));
  feed.handle(other.data(), static_cast<int>(other.size()), "GROUNDSIM_CONTACT_s2");
  EXPECT_EQ(r.delivered.size(), 1u);
  EXPECT_EQ(feed.forwarded(), 1u);
  EXPECT_EQ(feed.undecodable(), 0u);
}

TEST(ContactFeed, UndecodableDatagramsAreCountedAndDropped) {
  Recorder r;
  ContactFeed feed(nullptr, r.hooks("s1"));
  auto good = encoded(contactState("s1"));
  const std::string garbage = "not a contact_state_t at all";
  std::vector<std::uint8_t> truncated(good.begin(), good.begin() + static_cast<long>(good.size() / 2));
  // an object count far beyond the bytes that follow
  std::vector<std::uint8_t> lying = good;
  groundsim::state_t wrong{};
  wrong.session_id = "s1";
  const auto wrong_type = encoded(wrong);
  feed.handle(garbage.data(), static_cast<int>(garbage.size()), "GROUNDSIM_CONTACT_s1");
  feed.handle(truncated.data(), static_cast<int>(truncated.size()), "GROUNDSIM_CONTACT_s1");
  feed.handle(wrong_type.data(), static_cast<int>(wrong_type.size()), "GROUNDSIM_CONTACT_s1");
  feed.handle(nullptr, 0, "GROUNDSIM_CONTACT_s1");
  // nobjects sits after the fingerprint, utime, seq, the session id (length + bytes + NUL) and t
  const size_t at = 8 + 8 + 8 + 4 + 3 + 8;
  lying[at] = 0x7f;
  feed.handle(lying.data(), static_cast<int>(lying.size()), "GROUNDSIM_CONTACT_s1");
  EXPECT_EQ(feed.undecodable(), 5u);
  EXPECT_EQ(r.bad.size(), 5u);
  EXPECT_TRUE(r.delivered.empty());
  // and the next good one still goes through
  feed.handle(good.data(), static_cast<int>(good.size()), "GROUNDSIM_CONTACT_s1");
  EXPECT_EQ(r.delivered.size(), 1u);
}

TEST(ObjectLayout, ObjectsArePlacedAsTheSceneBuildsThem) {
  const std::string doc = R"({"name": "objects", "duration": 1, "ground": {"type": "plane"},
    "vehicle": {"name": "car", "initial": {"position": [0, 0, 0]}},
    "objects": [
      {"name": "barrier", "shape": "box", "size": [0.6, 12, 1.0], "position": [40, 0, 0], "yaw_deg": 90},
      {"name": "kerb", "shape": "box", "size": [4, 0.3, 0.15], "rounding": 0.05, "position": [10, 5, 0]},
      {"name": "cone1", "shape": "cone", "radius": 0.18, "top_radius": 0.03, "height": 0.7, "mass": 3,
       "position": [20, -5, 0]},
      {"name": "ball", "shape": "sphere", "radius": 0.4, "position": [10, -8, 3], "on_ground": false},
      {"name": "post", "shape": "capsule", "radius": 0.2, "height": 1.5, "position": [-10, 6, 0]}
    ]})";
  const auto view = makeSceneView(doc);
  const json& objs = view->layout["objects"];
  ASSERT_EQ(objs.size(), 5u);
  const json& barrier = objs[0];
  EXPECT_EQ(barrier["name"], "barrier");
  EXPECT_EQ(barrier["shape"], "box");
  EXPECT_EQ(barrier["static"], true);
  EXPECT_NEAR(barrier["size"][0].get<double>(), 0.6, 1e-12);
  EXPECT_NEAR(barrier["size"][1].get<double>(), 12.0, 1e-12);
  EXPECT_NEAR(barrier["size"][2].get<double>(), 1.0, 1e-12);
  // on the ground: its centre half its height above the plane
  EXPECT_NEAR(barrier["p"][0].get<double>(), 40.0, 1e-9);
  EXPECT_NEAR(barrier["p"][2].get<double>(), 0.5, 1e-9);
  // yawed 90 degrees about z: w = z = cos 45
  EXPECT_NEAR(barrier["q"][0].get<double>(), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(std::abs(barrier["q"][3].get<double>()), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(objs[1]["rounding"].get<double>(), 0.05, 1e-12);
  EXPECT_NEAR(objs[1]["p"][2].get<double>(), 0.075, 1e-9);
  const json& cone = objs[2];
  EXPECT_EQ(cone["shape"], "cone");
  EXPECT_EQ(cone["static"], false);
  EXPECT_NEAR(cone["mass"].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(cone["radius"].get<double>(), 0.18, 1e-12);
  EXPECT_NEAR(cone["top_radius"].get<double>(), 0.03, 1e-12);
  EXPECT_NEAR(cone["height"].get<double>(), 0.7, 1e-12);
  // the shape's centre (not its centre of mass, lower in a cone)
  EXPECT_NEAR(cone["p"][0].get<double>(), 20.0, 1e-6);
  EXPECT_NEAR(cone["p"][1].get<double>(), -5.0, 1e-6);
  EXPECT_NEAR(cone["p"][2].get<double>(), 0.35, 1e-6);
  EXPECT_NEAR(objs[3]["p"][2].get<double>(), 3.0, 1e-9);  // placed freely
  EXPECT_NEAR(objs[4]["height"].get<double>(), 1.5, 1e-12);  // end to end
  EXPECT_NEAR(objs[4]["p"][2].get<double>(), 0.75, 1e-9);
}
