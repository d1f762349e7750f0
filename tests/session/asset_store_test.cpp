// The server's asset store: parts put together, every hash checked, every
// bound held (per file, per client's unfinished uploads, in total), and
// only assets no session holds evicted.
#include <gtest/gtest.h>

#include <chrono>

#include "scenario/assets.hpp"
#include "session/asset_store.hpp"

namespace groundsim::session {
namespace {

const TimePoint kT0{};

std::string bytesOf(std::size_t n, unsigned seed) {
  std::string s(n, '\0');
  for (std::size_t i = 0; i < n; ++i) s[i] = static_cast<char>((i * 131 + seed * 7919) % 251);
  return s;
}

// Part i of `bytes` as a client sends it.
AssetPart partOf(const std::string& bytes, int i, const std::string& client = "c1", const std::string& name = "h.png") {
  AssetPart p;
  p.client_id = client;
  p.name = name;
  p.sha256 = scenario::sha256Hex(bytes);
  p.size = bytes.size();
  p.nparts = assetParts(bytes.size());
  p.part = i;
  const std::size_t begin = static_cast<std::size_t>(i) * kAssetPartBytes;
  p.data = bytes.substr(begin, std::min<std::size_t>(kAssetPartBytes, bytes.size() - begin));
  return p;
}

scenario::AssetRef refOf(const std::string& bytes, const std::string& name = "h.png") {
  return {name, scenario::sha256Hex(bytes), bytes.size()};
}

TEST(AssetStore, PartsInAnyOrderMakeTheFileAndItsHashIsChecked) {
  AssetStore store;
  const std::string file = bytesOf(3 * kAssetPartBytes + 17, 1);  // 4 parts, the last short
  ASSERT_EQ(assetParts(file.size()), 4);
  std::string why;
  auto missing = store.missing({refOf(file)}, &why);
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0].parts, (std::vector<int>{0, 1, 2, 3}));
  for (int i : {2, 0, 3}) EXPECT_EQ(store.addPart(partOf(file, i), kT0), "");
  missing = store.missing({refOf(file)}, &why);
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0].parts, (std::vector<int>{1}));  // only what was lost
  EXPECT_EQ(store.find(refOf(file).sha256), nullptr);
  EXPECT_EQ(store.addPart(partOf(file, 0), kT0), "");  // a repeat changes nothing
  EXPECT_EQ(store.addPart(partOf(file, 1), kT0), "");
  auto got = store.find(refOf(file).sha256);
  ASSERT_NE(got, nullptr);
  EXPECT_EQ(*got, file);
  EXPECT_TRUE(store.missing({refOf(file)}, &why).empty());
  EXPECT_EQ(store.stats().pending_bytes, 0u);
}

TEST(AssetStore, BytesThatDoNotMatchTheirHashAreDiscardedNamingTheFile) {
  AssetStore store;
  const std::string file = bytesOf(1000, 2);
  AssetPart p = partOf(file, 0);
  p.data[10] ^= 1;  // corrupted on the way
  const std::string why = store.addPart(p, kT0);
  EXPECT_NE(why.find("\"h.png\""), std::string::npos) << why;
  EXPECT_NE(why.find("hash to sha256"), std::string::npos) << why;
  EXPECT_EQ(store.find(p.sha256), nullptr);
  EXPECT_EQ(store.stats().bytes + store.stats().pending_bytes, 0u);
}

TEST(AssetStore, MalformedPartsAreRefusedNamingWhatIsWrong) {
  AssetLimits lim;
  lim.max_asset_bytes = 1 << 20;
  AssetStore store(lim);
  const std::string file = bytesOf(2 * kAssetPartBytes, 3);
  AssetPart truncated = partOf(file, 0);
  truncated.data.resize(100);
  EXPECT_NE(store.addPart(truncated, kT0).find("truncated"), std::string::npos);
  AssetPart wrong_count = partOf(file, 0);
  wrong_count.nparts = 7;
  EXPECT_NE(store.addPart(wrong_count, kT0).find("nparts 7"), std::string::npos);
  AssetPart outside = partOf(file, 1);
  outside.part = 2;
  EXPECT_NE(store.addPart(outside, kT0).find("outside"), std::string::npos);
  AssetPart bad_hash = partOf(file, 0);
  bad_hash.sha256 = "XYZ";
  EXPECT_NE(store.addPart(bad_hash, kT0).find("sha256"), std::string::npos);
  // a 10^12-byte announcement is refused from its header: nothing is allocated
  AssetPart huge = partOf(file, 0);
  huge.size = 1'000'000'000'000ull;
  huge.nparts = assetParts(huge.size);
  const std::string why = store.addPart(huge, kT0);
  EXPECT_NE(why.find("--max-asset-bytes"), std::string::npos) << why;
  EXPECT_EQ(store.stats().pending_bytes, 0u);
  // the same bound on a create's manifest, before any part is sent
  std::string manifest_why;
  EXPECT_TRUE(store.missing({{"big.png", huge.sha256, huge.size}}, &manifest_why).empty());
  EXPECT_NE(manifest_why.find("/assets/big.png/size"), std::string::npos) << manifest_why;
}

TEST(AssetStore, AScenarioMayNotNameMoreThanItsShare) {
  AssetLimits lim;
  lim.max_asset_bytes = 1000;
  lim.max_session_bytes = 1500;
  AssetStore store(lim);
  std::string why;
  const auto a = refOf(bytesOf(900, 1), "a.png"), b = refOf(bytesOf(900, 2), "b.png");
  store.missing({a, b}, &why);
  EXPECT_NE(why.find("--max-session-asset-bytes"), std::string::npos) << why;
}

TEST(AssetStore, HeldAssetsStayAndUnheldOnesAreEvictedOldestFirst) {
  AssetLimits lim;
  lim.cache_bytes = 3000;
  lim.max_asset_bytes = 3000;
  AssetStore store(lim);
  const std::string a = bytesOf(1000, 1), b = bytesOf(1000, 2), c = bytesOf(1000, 3), d = bytesOf(1500, 4);
  ASSERT_EQ(store.addPart(partOf(a, 0), kT0), "");
  ASSERT_EQ(store.addPart(partOf(b, 0), kT0), "");
  ASSERT_EQ(store.addPart(partOf(c, 0), kT0), "");
  auto held = store.find(refOf(a).sha256);  // a session holds a (and a was just used)
  std::string why;
  store.missing({refOf(c)}, &why);          // c used after b: b is the oldest unheld
  ASSERT_EQ(store.addPart(partOf(d, 0), kT0), "");  // 1500 more: b (1000) and then c go, a stays
  EXPECT_NE(store.find(refOf(a).sha256), nullptr);
  EXPECT_EQ(store.find(refOf(b).sha256), nullptr);
  EXPECT_EQ(store.find(refOf(c).sha256), nullptr);
  EXPECT_LE(store.stats().bytes, lim.cache_bytes);
  // a (1000) and d (1500) held: 1000 more do not fit, and nothing held is evicted
  auto held_d = store.find(refOf(d).sha256);
  ASSERT_NE(held_d, nullptr);
  const std::string refused = store.addPart(partOf(bytesOf(1000, 5), 0), kT0);
  EXPECT_NE(refused.find("--asset-cache-bytes"), std::string::npos) << refused;
  EXPECT_EQ(*store.find(refOf(a).sha256), a);
  EXPECT_EQ(*held_d, d);
}

TEST(AssetStore, AClientsUnfinishedUploadsAreBoundedAndExpire) {
  AssetLimits lim;
  lim.max_pending_per_client = 2;
  lim.pending_timeout = 30;
  AssetStore store(lim);
  const std::string f1 = bytesOf(2 * kAssetPartBytes, 1), f2 = bytesOf(2 * kAssetPartBytes, 2),
                    f3 = bytesOf(2 * kAssetPartBytes, 3);
  EXPECT_EQ(store.addPart(partOf(f1, 0), kT0), "");
  EXPECT_EQ(store.addPart(partOf(f2, 0), kT0), "");
  EXPECT_NE(store.addPart(partOf(f3, 0), kT0).find("unfinished uploads"), std::string::npos);
  EXPECT_EQ(store.addPart(partOf(f3, 0, "c2"), kT0), "");  // another client is not held back
  store.expire(kT0 + std::chrono::seconds(31));
  EXPECT_EQ(store.stats().pending, 0u);
  EXPECT_EQ(store.stats().pending_bytes, 0u);
  EXPECT_EQ(store.addPart(partOf(f3, 0), kT0 + std::chrono::seconds(31)), "");
}

TEST(AssetStore, AnEmptyFileIsOnePartOfNoBytes) {
  AssetStore store;
  const std::string empty;
  EXPECT_EQ(store.addPart(partOf(empty, 0), kT0), "");
  auto got = store.find(scenario::sha256Hex(empty));
  ASSERT_NE(got, nullptr);
  EXPECT_TRUE(got->empty());
}

}  // namespace
}  // namespace groundsim::session
