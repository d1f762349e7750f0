// Scenarios that travel with their files, against the real groundsim-server
// started as the README starts it (no --terrain-dir) and the real CLI:
// every shipped scenario creates; a second create of the same terrain
// sends hashes only; parts lost on the way are asked for again; bad parts
// are answered with an error naming the file while the server keeps
// serving (docs/protocol.md, Assets).
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <groundsim/asset_part_t.hpp>
#include <groundsim/asset_want_t.hpp>
#include <groundsim/event_t.hpp>

#include "process.hpp"
#include "protocol/channels.hpp"
#include "protocol/codec.hpp"
#include "scenario/assets.hpp"
#include "test_env.hpp"

namespace groundsim::itest {
namespace {

namespace fs = std::filesystem;
const std::string kConfigs = GROUNDSIM_CONFIG_DIR;

// Counts asset parts and wants on the bus and keeps the error events.
class BusTap {
 public:
  BusTap() : lcm_(kUrl) {
    lcm_.subscribe(net::kAssetChannel, &BusTap::onPart, this)->setQueueCapacity(100000);
    lcm_.subscribe(net::kAssetWantChannel, &BusTap::onWant, this)->setQueueCapacity(100000);
    lcm_.subscribe(net::kEventChannel, &BusTap::onEvent, this)->setQueueCapacity(100000);
    thread_ = std::thread([this] {
      while (!stop_) lcm_.handleTimeout(20);
    });
  }
  ~BusTap() {
    stop_ = true;
    thread_.join();
  }
  lcm::LCM& lcm() { return lcm_; }
  int parts() const { return parts_; }
  // The parts counted once the tap's receive thread has caught up: at least
  // `least` of them, then none more for 300 ms (bounded; under load the
  // thread may still be reading datagrams a finished client sent).
  int settledParts(int least) {
    for (double t = 0; t < 20 && parts_ < least; t += 0.02) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    for (int n = -1; n != parts_;) {
      n = parts_;
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    return parts_;
  }
  int wants() const { return wants_; }
  // Waits (bounded) for an error event whose reason contains text.
  std::string waitForEvent(const std::string& text, double timeout_s = 20) {
    for (double t = 0; t < timeout_s; t += 0.05) {
      {
        std::lock_guard<std::mutex> lk(m_);
        for (const auto& e : events_)
          if (e.find(text) != std::string::npos) return e;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return "";
  }

 private:
  void onPart(const lcm::ReceiveBuffer*, const std::string&) { ++parts_; }
  void onWant(const lcm::ReceiveBuffer*, const std::string&) { ++wants_; }
  void onEvent(const lcm::ReceiveBuffer* b, const std::string&) {
    groundsim::event_t e;
    if (!net::decodeMessage(b->data, static_cast<int>(b->data_size), e, "groundsim.event_t").ok()) return;
    std::lock_guard<std::mutex> lk(m_);
    events_.push_back(e.channel + " " + e.reason);
  }
  lcm::LCM lcm_;
  std::atomic<bool> stop_{false};
  std::atomic<int> parts_{0}, wants_{0};
  std::mutex m_;
  std::vector<std::string> events_;
  std::thread thread_;
};

class Assets : public ::testing::Test {
 protected:
  void SetUp() override {
    token_file_ = tokenFile("assets");
    std::remove(token_file_.c_str());
    // as the README starts it, but for the test's URL and room for every
    // shipped scenario's create from this one client (--client-*: 0, no limit)
    server_ = std::make_unique<Process>(std::vector<std::string>{kServer, "--lcm-url", kUrl, "--max-sessions", "64",
                                                                 "--client-sessions", "0", "--client-creates", "0"});
    ASSERT_TRUE(server_->waitForOutput("groundsim-server ready", 20)) << server_->wait(1).err;
  }
  void TearDown() override {
    server_->signal(SIGTERM);
    server_->wait(30);
    std::remove(token_file_.c_str());
    std::remove((token_file_ + ".lock").c_str());
  }
  Result cli(std::vector<std::string> args) {
    args.insert(args.begin(), kCli);
    args.insert(args.end(), {"--lcm-url", kUrl, "--token-file", token_file_});
    withReplyTimeout(args);
    return run(args, "", 120);
  }
  std::unique_ptr<Process> server_;
  std::string token_file_;
};

TEST_F(Assets, EveryShippedScenarioCreatesThroughTheCli) {
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(kConfigs))
    if (e.path().extension() == ".json") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 15u);  // 19 when written
  for (const std::string& f : files) {
    const Result r = cli({"create", f, "--duration", "1"});
    EXPECT_EQ(r.status, 0) << f << ": " << r.err;
    const std::string id = lastLine(r.out);
    if (r.status == 0) EXPECT_EQ(cli({"stop", id}).status, 0) << f;
  }
}

TEST_F(Assets, ASecondCreateOfTheSameTerrainSendsOnlyHashes) {
  BusTap tap;
  const std::string hills = kConfigs + "/hills.json";
  const Result first = cli({"create", hills, "--duration", "1"});
  ASSERT_EQ(first.status, 0) << first.err;
  // hills.png is 128 kB: three parts of 56 KiB, asked for once
  const auto size = fs::file_size(kConfigs + "/terrain/hills.png");
  const int sent = tap.settledParts(static_cast<int>((size + 57343) / 57344));
  EXPECT_EQ(sent, static_cast<int>((size + 57343) / 57344));
  EXPECT_EQ(tap.wants(), 1);
  const Result second = cli({"create", hills, "--duration", "1"});
  ASSERT_EQ(second.status, 0) << second.err;
  // the terrain is the same bytes under another scenario too
  const Result goal = cli({"create", kConfigs + "/tasks/goal.json", "--duration", "1"});
  ASSERT_EQ(goal.status, 0) << goal.err;
  EXPECT_EQ(tap.settledParts(sent), sent);
  EXPECT_EQ(tap.wants(), 1);
}

TEST_F(Assets, PartsLostOnTheWayAreAskedForAgain) {
  BusTap tap;
  // the valley road sent by hand with its middle part left out, as a lossy link would
  const std::string path = kConfigs + "/terrain/valley_road.png";
  const std::string bytes = readText(path);
  const std::string sha = scenario::sha256Hex(bytes);
  const int nparts = static_cast<int>((bytes.size() + 57343) / 57344);
  ASSERT_GE(nparts, 2);
  for (int p = 0; p < nparts; ++p) {
    if (p == 1) continue;
    groundsim::asset_part_t m{};
    m.client_id = "lossy";
    m.name = "terrain/valley_road.png";
    m.sha256 = sha;
    m.size = static_cast<std::int64_t>(bytes.size());
    m.part = p;
    m.nparts = nparts;
    const std::size_t begin = static_cast<std::size_t>(p) * 57344;
    m.data.assign(bytes.begin() + begin, bytes.begin() + std::min(bytes.size(), begin + 57344));
    m.nbytes = static_cast<std::int32_t>(m.data.size());
    ASSERT_EQ(tap.lcm().publish(net::kAssetChannel, &m), 0);
  }
  const int before = tap.settledParts(nparts - 1);  // the tap hears its own parts too
  const Result r = cli({"create", kConfigs + "/sedan_hills.json", "--duration", "1"});
  ASSERT_EQ(r.status, 0) << r.err;
  // the server asked for the one part it lacked, and only that one was sent
  EXPECT_EQ(tap.settledParts(before + 1) - before, 1);
}

TEST_F(Assets, BadPartsAreAnsweredNamingTheFileAndTheServerKeepsServing) {
  BusTap tap;
  groundsim::asset_part_t m{};
  m.client_id = "hostile";
  m.name = "fake.png";
  m.sha256 = scenario::sha256Hex("what was announced");
  m.data = {'s', 'o', 'm', 'e', 't', 'h', 'i', 'n', 'g', ' ', 'e', 'l', 's', 'e'};
  m.nbytes = static_cast<std::int32_t>(m.data.size());
  m.size = m.nbytes;
  m.part = 0;
  m.nparts = 1;
  ASSERT_EQ(tap.lcm().publish(net::kAssetChannel, &m), 0);
  EXPECT_NE(tap.waitForEvent("\"fake.png\" (sha256"), "");
  EXPECT_NE(tap.waitForEvent("hash to sha256"), "");
  // a 10^12-byte announcement, a wrong part count, a datagram that is no part
  m.size = 1'000'000'000'000;
  ASSERT_EQ(tap.lcm().publish(net::kAssetChannel, &m), 0);
  EXPECT_NE(tap.waitForEvent("--max-asset-bytes"), "");
  m.size = m.nbytes;
  m.nparts = 5;
  ASSERT_EQ(tap.lcm().publish(net::kAssetChannel, &m), 0);
  EXPECT_NE(tap.waitForEvent("nparts 5"), "");
  const char junk[] = "not an asset part at all";
  ASSERT_EQ(tap.lcm().publish(net::kAssetChannel, junk, sizeof junk), 0);
  EXPECT_NE(tap.waitForEvent("GROUNDSIM_ASSET fingerprint"), "");
  // a create whose manifest announces more than the server takes is refused naming the key
  const std::string big = (fs::temp_directory_path() / ("gs-assets-big-" + std::to_string(getpid()) + ".json")).string();
  {
    std::string doc = readText(kConfigs + "/plain.json");
    doc.insert(doc.find('{') + 1, R"("assets": {"x.png": {"sha256": ")" + std::string(64, 'a') +
                                      R"(", "size": 1000000000000}},)");
    FILE* f = std::fopen(big.c_str(), "w");
    std::fputs(doc.c_str(), f);
    std::fclose(f);
  }
  const Result refused = cli({"create", big});
  std::remove(big.c_str());
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("/assets/x.png/size"), std::string::npos) << refused.err;
  // and it keeps serving
  const Result ok = cli({"create", kConfigs + "/hills.json", "--duration", "1"});
  EXPECT_EQ(ok.status, 0) << ok.err;
}

}  // namespace
}  // namespace groundsim::itest
