// Files that travel with a scenario (scenario/assets.hpp): a client finds
// the files a scenario names without reading them, attaches their hashes;
// a server builds from the bytes it was sent, exactly as from the files;
// bad bytes are refused under the key that names them, for one reason.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "files.hpp"
#include "scenario/assets.hpp"
#include "scenario/scenario.hpp"
#include "scenario/terrain_loader.hpp"

using namespace groundsim;
using namespace groundsim::scenario;
using namespace groundsim::test;
using nlohmann::json;

namespace {

const std::string kConfigs = std::string(GROUNDSIM_SOURCE_DIR) + "/configs";

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

json goalDoc() { return json::parse(readAll(kConfigs + "/tasks/goal.json")); }

std::vector<Issue> issuesOf(const json& doc, const FileAccess& files) {
  try {
    parseScenario(doc, Budget{}, files);
  } catch (const ScenarioError& e) {
    return e.issues();
  }
  ADD_FAILURE() << "document was accepted";
  return {};
}

std::string listed(const std::vector<Issue>& issues) {
  std::string all;
  for (const Issue& i : issues) all += "\n  " + i.str();
  return all;
}

// A PNG header (signature + IHDR with its CRC) and nothing else.
std::string pngHeader(std::uint32_t w, std::uint32_t h, int depth) {
  auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                       static_cast<char>(v)};
  };
  std::string chunk = "IHDR" + be32(w) + be32(h) + std::string{static_cast<char>(depth), 0, 0, 0, 0};
  std::uint32_t crc = 0xffffffffu;  // CRC-32 of the chunk type and data (PNG spec, annex D)
  for (unsigned char c : chunk) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + chunk + be32(crc ^ 0xffffffffu);
}

TEST(Assets, AClientFindsTheFilesAScenarioNamesWithoutReadingThem) {
  EXPECT_EQ(namedFiles(goalDoc()), (std::vector<std::string>{"../terrain/hills.png"}));
  const json hills = json::parse(readAll(kConfigs + "/hills.json"));
  const auto names = namedFiles(hills);
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "terrain/hills.png");
  EXPECT_TRUE(namedFiles(json::parse(readAll(kConfigs + "/plain.json"))).empty());
  // a friction map's file is found too, and a name used twice is listed once
  json g = {{"type", "heightfield"}, {"file", "a.csv"}, {"cell_size", 1.0},
            {"friction_map", {{"file", "mu.png"}, {"cell_size", 1.0}}}};
  json doc = {{"vehicle", json::object()}, {"ground", g}};
  EXPECT_EQ(namedFiles(doc), (std::vector<std::string>{"a.csv", "mu.png"}));
}

TEST(Assets, BytesSentWithTheScenarioBuildTheSameGroundAsTheFile) {
  json doc = goalDoc();
  const auto assets = attachAssets(doc, kConfigs + "/tasks", 64u << 20);
  ASSERT_EQ(assets.size(), 1u);
  const std::string file = readAll(kConfigs + "/terrain/hills.png");
  EXPECT_EQ(*assets[0].bytes, file);
  EXPECT_EQ(assets[0].ref.sha256, sha256Hex(file));
  EXPECT_EQ(doc["assets"]["../terrain/hills.png"]["size"].get<std::uint64_t>(), file.size());
  // SHA-256 itself, against the FIPS 180-2 example
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");

  auto bytes = std::make_shared<AssetBytes>();
  (*bytes)["../terrain/hills.png"] = assets[0].bytes;
  const Scenario remote = parseScenario(doc, Budget{}, FileAccess::fromAssets(bytes));
  const Scenario local = parseScenario(goalDoc(), Budget{}, FileAccess::local(kConfigs + "/tasks"));
  ASSERT_TRUE(remote.ground.heightfield && local.ground.heightfield);
  for (double x : {-100.0, -3.3, 0.0, 17.25, 90.0})
    for (double y : {-50.0, 0.5, 44.0}) EXPECT_EQ(remote.ground.heightfield->height(x, y), local.ground.heightfield->height(x, y));
  ASSERT_EQ(remote.assets.size(), 1u);
  EXPECT_EQ(remote.assets[0].sha256, sha256Hex(file));
}

TEST(Assets, AFileNotSentIsOneIssueNamingIt) {
  // no bytes at all: one issue under the key that names the file, and the
  // PNG's height_scale is not reported as a second problem
  const auto issues = issuesOf(goalDoc(), FileAccess::fromAssets(std::make_shared<AssetBytes>()));
  ASSERT_EQ(issues.size(), 1u) << listed(issues);
  EXPECT_EQ(issues[0].path, "/ground/file");
  EXPECT_NE(issues[0].message.find("\"../terrain/hills.png\" was not sent with the scenario"), std::string::npos)
      << issues[0].message;
  const auto none = issuesOf(goalDoc(), FileAccess::none());
  ASSERT_EQ(none.size(), 1u) << listed(none);
  EXPECT_EQ(none[0].path, "/ground/file");
}

TEST(Assets, BadBytesAreRefusedForTheirOwnReason) {
  auto named = [](const std::string& bytes) {
    auto m = std::make_shared<AssetBytes>();
    (*m)["../terrain/hills.png"] = std::make_shared<const std::string>(bytes);
    return issuesOf(goalDoc(), FileAccess::fromAssets(m));
  };
  const std::string png = readAll(kConfigs + "/terrain/hills.png");
  struct Case {
    std::string bytes, expect;
  } cases[] = {
      {"hello, not an image", "not a PNG file"},
      {png.substr(0, png.size() / 2), "truncated"},
      {png.substr(0, 30), "bad PNG"},
      // a 1 x 10^9 header is refused from its header, before any row is allocated
      {pngHeader(1, 1'000'000'000u, 16), "1 x 1000000000 = 1000000000 samples, more than the limit"},
      {pngHeader(70000, 70000, 8), "more than the limit"},
      {"", "not a PNG file"},
  };
  for (const Case& c : cases) {
    const auto issues = named(c.bytes);
    ASSERT_EQ(issues.size(), 1u) << c.expect << listed(issues);
    EXPECT_EQ(issues[0].path, "/ground/file");
    EXPECT_NE(issues[0].message.find(c.expect), std::string::npos) << issues[0].message;
    EXPECT_NE(issues[0].message.find("\"hills.png\""), std::string::npos) << issues[0].message;
  }
}

TEST(Assets, TheManifestIsValidatedByPath) {
  json doc = goalDoc();
  doc["assets"] = {{"../terrain/hills.png", {{"sha256", "ABC"}, {"size", -1}, {"colour", 1}}}};
  const auto issues = issuesOf(doc, FileAccess::local(kConfigs + "/tasks"));
  const std::string all = listed(issues);
  EXPECT_NE(all.find("/assets/..~1terrain~1hills.png/sha256: must be 64 lowercase hex digits"), std::string::npos)
      << all;
  EXPECT_NE(all.find("/assets/..~1terrain~1hills.png/size"), std::string::npos) << all;
  EXPECT_NE(all.find("/assets/..~1terrain~1hills.png/colour: unknown key"), std::string::npos) << all;
  doc["assets"] = "hills.png";
  EXPECT_NE(listed(issuesOf(doc, FileAccess::local(kConfigs + "/tasks"))).find("/assets: expected an object"),
            std::string::npos);
}

TEST(Assets, AFileThatCannotBeReadIsNamedBeforeAnythingIsSent) {
  TempDir dir;
  json doc = goalDoc();
  EXPECT_THROW(
      {
        try {
          attachAssets(doc, dir.path.string(), 64u << 20);
        } catch (const ScenarioError& e) {
          EXPECT_NE(std::string(e.what()).find("hills.png"), std::string::npos) << e.what();
          throw;
        }
      },
      ScenarioError);
  // larger than the client's limit: refused unread
  writePng(dir / "terrain" / "hills.png", 64, 64, 16, {});
  json near = goalDoc();
  near["ground"]["file"] = "terrain/hills.png";
  EXPECT_THROW(attachAssets(near, dir.path.string(), 10), ScenarioError);
  EXPECT_EQ(attachAssets(near, dir.path.string(), 1u << 20).size(), 1u);
}

}  // namespace
