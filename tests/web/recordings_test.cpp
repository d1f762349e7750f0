// The bridge's recordings (web/bridge/recordings.*): a folder's MCAP files
// listed with their sessions, a window and an instant of a session read
// with seeking, and hostile requests (paths out of the folder, bad numbers,
// unknown sessions) answered with the parameter and the reason.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "support/temp_dir.hpp"
#include "bridge/recordings.hpp"
#include "recording/mcap_writer.hpp"
#include "scenario/assets.hpp"

namespace groundsim::web {
namespace {

using groundsim::test::processTempDir;

// Two sessions at 100 Hz for 60 s, each in its own chunks, as the recorder writes them.
// (a folder per test: ctest runs them in parallel)
std::string folder() {
  const std::string dir =
      (processTempDir() / ("recordings_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())))
          .string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  recording::WriterOptions o;
  o.chunk_bytes = 64 << 10;
  recording::McapWriter w(dir + "/two.mcap", o);
  const auto schema = w.addSchema("groundsim.state", "jsonschema", "{}");
  const auto a = w.addChannel(schema, "/A1/state", "json");
  const auto b = w.addChannel(schema, "/B2/state", "json");
  for (int k = 0; k <= 6000; ++k) {
    const std::uint64_t t = static_cast<std::uint64_t>(k) * 10'000'000u;
    for (auto [ch, g] : {std::pair{a, 0}, std::pair{b, 1}})
      w.write(ch, static_cast<std::uint32_t>(k), t, t,
              "{\"seq\":" + std::to_string(k) + ",\"t\":" + std::to_string(k * 0.01) + ",\"x\":" + std::to_string(k) + "}", g);
  }
  w.close();
  return dir;
}

nlohmann::json body(const HttpAnswer& a) { return nlohmann::json::parse(a.body); }

// A refused request: its status, a JSON body naming `word` (the parameter).
void expectRefused(const Recordings& r, const std::string& path, const std::string& query, int status,
                   const std::string& word) {
  const HttpAnswer a = r.answer(path, query);
  EXPECT_EQ(a.status, status) << path << "?" << query << ": " << a.body;
  EXPECT_NE(a.body.find(word), std::string::npos) << a.body;
  EXPECT_NO_THROW(body(a));
}

TEST(Recordings, ListedWithTheirSessionsAndSpans) {
  const Recordings r(folder());
  const HttpAnswer a = r.answer("/recordings", "");
  ASSERT_EQ(a.status, 200) << a.body;
  const auto j = body(a);
  ASSERT_EQ(j["recordings"].size(), 1u);
  const auto& f = j["recordings"][0];
  EXPECT_EQ(f["name"], "two.mcap");
  EXPECT_TRUE(f["complete"].get<bool>());
  ASSERT_EQ(f["sessions"].size(), 2u);
  EXPECT_EQ(f["sessions"][0]["id"], "A1");
  EXPECT_EQ(f["sessions"][0]["states"], 6001);
  EXPECT_NEAR(f["sessions"][0]["t1"].get<double>(), 60.0, 1e-9);
}

TEST(Recordings, AWindowAndAnInstantAreReadWithSeeking) {
  const Recordings r(folder());
  auto j = body(r.answer("/recordings/two.mcap/states", "session=B2&from=30&to=30.5"));
  ASSERT_EQ(j["states"].size(), 51u);
  EXPECT_EQ(j["states"][0]["seq"], 3000);
  EXPECT_EQ(j["states"][50]["seq"], 3050);
  EXPECT_FALSE(j["more"].get<bool>());
  j = body(r.answer("/recordings/two.mcap/states", "session=B2&from=0&to=60&max=10"));
  EXPECT_EQ(j["states"].size(), 10u);
  EXPECT_TRUE(j["more"].get<bool>());
  // the newest state at or before 42.004 s
  j = body(r.answer("/recordings/two.mcap/states", "session=A1&at=42.004"));
  ASSERT_EQ(j["states"].size(), 1u);
  EXPECT_EQ(j["states"][0]["seq"], 4200);
  // past the end: the last one
  j = body(r.answer("/recordings/two.mcap/states", "session=A1&at=1000"));
  EXPECT_EQ(j["states"][0]["seq"], 6000);
}

TEST(Recordings, HostileRequestsNameTheParameter) {
  const Recordings r(folder());
  const auto expect = [&](const std::string& path, const std::string& query, int status, const std::string& word,
                          const Recordings* from = nullptr) { expectRefused(from ? *from : r, path, query, status, word); };
  expect("/recordings/..%2F..%2Fetc%2Fpasswd", "", 400, "name");
  expect("/recordings/../two.mcap", "", 400, "name");
  expect("/recordings/nope.mcap", "", 404, "no recording");
  expect("/recordings/two.mcap/other", "", 404, "states");
  expect("/recordings/two.mcap/states", "", 400, "session");
  expect("/recordings/two.mcap/states", "session=A1", 400, "at=T");
  expect("/recordings/two.mcap/states", "session=A1&at=nan", 400, "at");
  expect("/recordings/two.mcap/states", "session=A1&from=-1&to=2", 400, "from");
  expect("/recordings/two.mcap/states", "session=A1&from=5&to=2", 400, "to");
  expect("/recordings/two.mcap/states", "session=A1&from=0&to=2&max=99999", 400, "max");
  expect("/recordings/two.mcap/states", "session=ZZ&at=1", 404, "session");
  // a file that is not MCAP: a 500 naming the reason, the bridge serves on
  const std::string dir = folder();
  { std::ofstream(dir + "/junk.mcap") << "not an mcap file"; }
  expect("/recordings/junk.mcap/states", "session=A1&at=1", 500, "cannot read");
  // and the listing names it without failing the others
  const auto j = body(r.answer("/recordings", ""));
  EXPECT_EQ(j["recordings"].size(), 2u);
  const Recordings off("");
  expect("/recordings", "", 404, "--recordings", &off);
}

// A recording of one session "S1" as the recorder writes it: the scenario
// (as the server publishes it: with its asset manifest) attached, the
// asset files attached only when `with_assets`, 3 states and 3 events.
std::string recordedScene(const std::string& config, bool with_assets) {
  const std::string dir =
      (processTempDir() / ("scene_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())))
          .string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = std::string(GROUNDSIM_CONFIG_DIR) + "/" + config;
  std::ifstream in(path);
  nlohmann::json doc = nlohmann::json::parse(in);
  const auto assets = scenario::attachAssets(doc, std::filesystem::path(path).parent_path().string(), 64u << 20);
  recording::McapWriter w(dir + "/scene.mcap", recording::WriterOptions{});
  const auto schema = w.addSchema("groundsim.state", "jsonschema", "{}");
  const auto st = w.addChannel(schema, "/S1/state", "json");
  const auto ev = w.addChannel(schema, "/S1/events", "json");
  const auto co = w.addChannel(schema, "/S1/contact", "json");
  w.attach("scenario/S1.json", "application/json", 0, doc.dump());
  if (with_assets)
    for (const auto& a : assets) w.attach("assets/S1/" + a.ref.name, "application/octet-stream", 0, *a.bytes);
  for (int k = 0; k < 3; ++k) {
    const std::uint64_t t = static_cast<std::uint64_t>(k) * 1'000'000'000u;
    w.write(st, k, t, t, "{\"seq\":" + std::to_string(k) + ",\"t\":" + std::to_string(k) + "}", 0);
    w.write(co, k, t, t, "{\"seq\":" + std::to_string(k) + ",\"objects\":[{\"name\":\"cone\",\"position\":[" +
                              std::to_string(k) + ",0,0]}]}", 0);
    w.write(ev, k, t, t, "{\"seq\":" + std::to_string(k) + ",\"reason\":\"race: {\\\"type\\\":\\\"lap\\\",\\\"lap\\\":" +
                              std::to_string(k + 1) + "}\"}", 0);
  }
  w.close();
  return dir;
}

TEST(Recordings, ASessionsSceneAndGroundAreBuiltFromItsRecordedScenario) {
  // the incline of configs/downhill.json: 30 degrees down along +x through the origin
  const Recordings r(recordedScene("downhill.json", true));
  auto j = body(r.answer("/recordings/scene.mcap/scene", "session=S1"));
  ASSERT_TRUE(j.contains("layout")) << j.dump();
  EXPECT_EQ(j["layout"]["ground"], "incline");
  ASSERT_EQ(j["layout"]["vehicles"].size(), 1u);
  EXPECT_EQ(j["layout"]["vehicles"][0]["wheels"].size(), 4u);  // the report's car
  j = body(r.answer("/recordings/scene.mcap/ground", "session=S1&cx=10&cy=-3"));
  ASSERT_EQ(j["op"], "ground");
  const int n = j["n"];
  const double x0 = j["x0"], step = j["step"];
  int checked = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      const auto& z = j["z"][i * n + k];
      if (z.is_null()) continue;
      EXPECT_NEAR(z.get<double>(), -(x0 + k * step) * std::tan(M_PI / 6), 0.5e-3 + 1e-9);  // sent to the millimetre
      ++checked;
    }
  EXPECT_EQ(checked, n * n);
  EXPECT_NEAR(x0 + (n / 2) * step, 10.0, step);
  // its events, in order
  j = body(r.answer("/recordings/scene.mcap/events", "session=S1"));
  ASSERT_EQ(j["events"].size(), 3u);
  EXPECT_EQ(j["events"][2]["seq"], 2);
  EXPECT_FALSE(j["more"].get<bool>());
  // a window's contact states beside its states (the objects a replay moves)
  j = body(r.answer("/recordings/scene.mcap/states", "session=S1&from=0&to=5&contacts=1"));
  ASSERT_EQ(j["states"].size(), 3u);
  ASSERT_EQ(j["contacts"].size(), 3u);
  EXPECT_EQ(j["contacts"][1]["objects"][0]["position"][0], 1);
  // cut at 2 states: the contacts stop at the last state's time
  j = body(r.answer("/recordings/scene.mcap/states", "session=S1&from=0&to=5&contacts=1&max=2"));
  EXPECT_EQ(j["states"].size(), 2u);
  EXPECT_EQ(j["contacts"].size(), 2u);
  EXPECT_TRUE(j["more"].get<bool>());
  // without contacts=1: none
  j = body(r.answer("/recordings/scene.mcap/states", "session=S1&from=0&to=5"));
  EXPECT_FALSE(j.contains("contacts"));
}

TEST(Recordings, FilesTheRecordingDoesNotHoldAreFoundAmongTheConfigsByHash) {
  // the circuit's heightfield (circuit.png) not attached: found in configs/
  const std::string dir = recordedScene("race/circuit.json", false);
  const Recordings found(dir, GROUNDSIM_CONFIG_DIR);
  auto j = body(found.answer("/recordings/scene.mcap/scene", "session=S1"));
  ASSERT_TRUE(j.contains("layout")) << j.dump();
  EXPECT_EQ(j["layout"]["ground"], "heightfield");
  EXPECT_TRUE(j["layout"].contains("track"));  // the race's ribbon
  // without the configs: a clear refusal naming the file
  const Recordings lost(dir);
  const HttpAnswer a = lost.answer("/recordings/scene.mcap/scene", "session=S1");
  EXPECT_EQ(a.status, 422) << a.body;
  EXPECT_NE(a.body.find("circuit.png"), std::string::npos) << a.body;
}

TEST(Recordings, SceneRequestsNameTheParameter) {
  const Recordings r(recordedScene("downhill.json", true));
  const auto expect = [&](const std::string& path, const std::string& query, int status, const std::string& word) {
    expectRefused(r, path, query, status, word);
  };
  expect("/recordings/scene.mcap/ground", "session=S1", 400, "cx");
  expect("/recordings/scene.mcap/ground", "session=S1&cx=1&cy=nan", 400, "cy");
  expect("/recordings/scene.mcap/ground", "session=S1&cx=1e300&cy=0", 400, "cx");
  expect("/recordings/scene.mcap/scene", "session=NOPE", 404, "NOPE");
  expect("/recordings/scene.mcap/events", "session=NOPE", 404, "NOPE");
  expect("/recordings/scene.mcap/scene", "", 400, "session");
  expect("/recordings/scene.mcap/states", "session=S1&from=0&to=1&contacts=yes", 400, "contacts");
}

}  // namespace
}  // namespace groundsim::web
