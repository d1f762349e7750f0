// Heightfields and friction from scenario documents: PNG 8 and 16 bit, CSV
// and inline rows give the same surface; every bad input is refused under
// its JSON path with the reason; file paths follow the access rules.
#include <gtest/gtest.h>

#include <cmath>

#include "files.hpp"
#include "physics/simulator.hpp"
#include "scenario/scenario.hpp"
#include "scenario/terrain_loader.hpp"

using namespace groundsim;
using namespace groundsim::scenario;
using namespace groundsim::test;
using nlohmann::json;

namespace {

constexpr double kPiForHills = 3.14159265358979323846;

json docWithGround(json ground) {
  json d = json::parse(R"({"vehicle": {}})");
  d["ground"] = std::move(ground);
  return d;
}

json hf(json extra) {
  json g = {{"type", "heightfield"}, {"cell_size", 0.5}, {"origin", {1.0, -2.0}}};
  if (extra.is_object()) g.update(extra);
  return g;
}

std::vector<Issue> issuesOf(const json& doc, const FileAccess& files) {
  try {
    parseScenario(doc, files);
  } catch (const ScenarioError& e) {
    return e.issues();
  }
  ADD_FAILURE() << "document was accepted";
  return {};
}

// The issue at `path` whose message contains `text`; fails otherwise.
::testing::AssertionResult hasIssue(const std::vector<Issue>& issues, const std::string& path,
                                    const std::string& text) {
  std::string all;
  for (const Issue& i : issues) {
    if (i.path == path && i.message.find(text) != std::string::npos) return ::testing::AssertionSuccess();
    all += "\n  " + i.str();
  }
  return ::testing::AssertionFailure() << "no issue at " << path << " containing \"" << text << "\"; got:" << all;
}

// 5 x 4 values in 0..255 with every row and column different
std::vector<unsigned> pattern() {
  std::vector<unsigned> v;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i) v.push_back((37 * i + 91 * j * j + 13) % 256);
  return v;
}

}  // namespace

TEST(TerrainFiles, Png8Png16CsvAndInlineRowsGiveTheSameHeights) {
  TempDir dir;
  const auto v8 = pattern();
  std::vector<unsigned> v16;
  for (unsigned v : v8) v16.push_back(v * 257);  // the same fraction of full scale
  writePng(dir / "h8.png", 5, 4, 8, v8);
  writePng(dir / "h16.png", 5, 4, 16, v16);
  const double scale = 3.0;
  std::string csv;
  json rows = json::array();
  for (int j = 0; j < 4; ++j) {
    json row = json::array();
    for (int i = 0; i < 5; ++i) {
      const double h = scale * v8[j * 5 + i] / 255.0;
      char buf[40];
      std::snprintf(buf, sizeof buf, "%s%.9g", i ? ", " : "", h);
      csv += buf;
      row.push_back(h);
    }
    csv += j % 2 ? "\r\n" : "\n";  // either line ending
    rows.push_back(row);
  }
  writeText(dir / "h.csv", csv + "\n");
  const FileAccess files = FileAccess::local(dir.path.string());
  std::vector<std::shared_ptr<const HeightfieldGround>> grounds;
  for (const json& extra : {json{{"file", "h8.png"}, {"height_scale", scale}},
                            json{{"file", "h16.png"}, {"height_scale", scale}}, json{{"file", "h.csv"}},
                            json{{"heights", rows}}}) {
    const Scenario s = parseScenario(docWithGround(hf(extra)), files);
    ASSERT_TRUE(s.ground.heightfield) << extra.dump();
    grounds.push_back(s.ground.heightfield);
  }
  // the samples land where the rules say: row j of the file at y0 + j cell
  const auto& g0 = *grounds[0];
  EXPECT_EQ(g0.nx(), 5);
  EXPECT_EQ(g0.ny(), 4);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 5; ++i)
      EXPECT_NEAR(g0.height(1.0 + 0.5 * i, -2.0 + 0.5 * j), scale * v8[j * 5 + i] / 255.0, 1e-5);
  for (size_t k = 1; k < grounds.size(); ++k)
    for (double x = 0.5; x < 4.0; x += 0.173)
      for (double y = -2.5; y < 0.0; y += 0.191)
        ASSERT_NEAR(grounds[k]->height(x, y), g0.height(x, y), 2e-6) << "source " << k;
}

TEST(TerrainFiles, BadFilesAreRefusedUnderTheFileKeyWithTheReason) {
  TempDir dir;
  const FileAccess files = FileAccess::local(dir.path.string());
  writeText(dir / "text.png", "this is not an image");
  writePng(dir / "good.png", 5, 4, 8, pattern());
  {  // a PNG cut short: the header is fine, the pixels are missing
    std::ifstream in(dir / "good.png", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    writeText(dir / "cut.png", bytes.substr(0, 45));
  }
  writePng(dir / "rgb.png", 3, 3, 8, std::vector<unsigned>(9, 7), PNG_COLOR_TYPE_RGB);
  writeText(dir / "ragged.csv", "1, 2, 3\n4, 5\n");
  writeText(dir / "nan.csv", "1, 2\n3, nan\n");
  writeText(dir / "word.csv", "1, 2\n3, abc\n");
  writeText(dir / "thin.csv", "1, 2, 3\n");
  writeText(dir / "h.tif", "");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"missing.png", "no such file"},
      {"text.png", "not a PNG file"},
      {"cut.png", "bad PNG"},
      {"rgb.png", "grayscale"},
      {"ragged.csv", "\"ragged.csv\" line 2: has 2 values, line 1 has 3"},
      {"nan.csv", "line 2, column 2: must be finite"},
      {"word.csv", "line 2, column 2: \"abc\" is not a number"},
      {"thin.csv", "at least 2 x 2"},
      {"h.tif", "unknown file type"},
  };
  for (const auto& [name, why] : cases)
    EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"file", name}})), files), "/ground/file", why)) << name;
}

TEST(TerrainFiles, TheSampleBudgetIsCheckedBeforeDecoding) {
  TempDir dir;
  writePng(dir / "huge.png", 4098, 4098, 8, {});  // 16.8 M samples of 0: a small file
  const auto issues = issuesOf(docWithGround(hf({{"file", "huge.png"}})), FileAccess::local(dir.path.string()));
  EXPECT_TRUE(hasIssue(issues, "/ground/file", "4098 x 4098 = 16793604 samples, more than the limit of 16785409"));
  // the loader's own limit applies to CSV just the same
  writeText(dir / "h.csv", "1, 2, 3\n4, 5, 6\n7, 8, 9\n");
  EXPECT_THROW(readCsv(dir / "h.csv", 8), TerrainError);
  EXPECT_EQ(readCsv(dir / "h.csv", 9).values.size(), 9u);
}

TEST(TerrainFiles, InlineRowsAndKeysAreValidatedByPath) {
  const FileAccess none = FileAccess::none();
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, 2}, {3}}}})), none), "/ground/heights/1",
                       "has 1 values, row 0 has 2"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, "a"}, {3, 4}}}})), none), "/ground/heights/0/1",
                       "expected a number, got string"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, 2}}}})), none), "/ground/heights",
                       "at least 2 x 2"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, 2}, {3, 4e7}}}})), none),
                       "/ground/heights/1/1", "must be within"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({})), none), "/ground/file", "missing required key"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"file", "a.csv"}, {"heights", {{1, 2}, {3, 4}}}})), none),
                       "/ground/heights", "not both"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, 2}, {3, 4}}}, {"height_scale", 2}})), none),
                       "/ground/height_scale", "PNG files only"));
  json no_cell = hf({{"heights", {{1, 2}, {3, 4}}}});
  no_cell.erase("cell_size");
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(no_cell), none), "/ground/cell_size", "missing required key"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, 2}, {3, 4}}}, {"cell_size", -1}})), none),
                       "/ground/cell_size", "must be"));
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"heights", {{1, 2}, {3, 4}}}, {"cel_size", 1}})), none),
                       "/ground/cel_size", "unknown key"));
}

TEST(TerrainPaths, FilesResolveAgainstTheScenarioDirectory) {
  TempDir dir;
  writePng(dir / "maps/terrain/h.png", 5, 4, 8, pattern());
  json doc = docWithGround(hf({{"file", "terrain/h.png"}}));
  writeText(dir / "maps/scene.json", doc.dump());
  // loadScenarioFile knows where the file is; the working directory is elsewhere
  EXPECT_TRUE(loadScenarioFile((dir / "maps/scene.json").string()).ground.heightfield);
  // the runner's rules also take absolute paths and ".."
  writeText(dir / "maps/up.json",
            docWithGround(hf({{"file", "../maps/terrain/h.png"}})).dump());
  EXPECT_TRUE(loadScenarioFile((dir / "maps/up.json").string()).ground.heightfield);
  EXPECT_TRUE(parseScenario(docWithGround(hf({{"file", (dir / "maps/terrain/h.png").string()}})),
                            FileAccess::local("/nonexistent"))
                  .ground.heightfield);
}

TEST(TerrainPaths, AServerReadsOnlyInsideItsTerrainDirectory) {
  TempDir dir;
  writePng(dir / "terrain/hills/h.png", 5, 4, 8, pattern());
  writePng(dir / "secret.png", 5, 4, 8, pattern());
  std::filesystem::create_symlink(dir / "secret.png", dir / "terrain/link.png");
  std::filesystem::create_directory_symlink(dir.path, dir / "terrain/up");
  const FileAccess server = FileAccess::confined((dir / "terrain").string());
  EXPECT_TRUE(parseScenario(docWithGround(hf({{"file", "hills/h.png"}})), server).ground.heightfield);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"../secret.png", "\"..\" is refused"},
      {"hills/../../secret.png", "\"..\" is refused"},
      {(dir / "secret.png").string(), "absolute paths are refused"},
      {"link.png", "leads out of the terrain directory"},
      {"up/secret.png", "leads out of the terrain directory"},
      {"nothing.png", "no such file in the terrain directory"},
      {"hills", "not a regular file"},
  };
  for (const auto& [name, why] : refused)
    EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"file", name}})), server), "/ground/file", why)) << name;
  // parsed from text, with no directory at all, no file is read
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(hf({{"file", (dir / "secret.png").string()}})), FileAccess::none()),
                       "/ground/file", "this scenario came without its files"));
}

TEST(TerrainScenes, TheReportCarAndTheLoneWheelRunOnAHeightfield) {
  // a gentle bowl, inline: 9 x 9 samples of 0.05 (x^2 + y^2) over +-8 m
  json rows = json::array();
  for (int j = 0; j < 9; ++j) {
    json row = json::array();
    for (int i = 0; i < 9; ++i) row.push_back(0.05 * ((i - 4) * (i - 4) + (j - 4) * (j - 4)) * 4.0);
    rows.push_back(row);
  }
  json ground = {{"type", "heightfield"}, {"cell_size", 2.0}, {"origin", {-8, -8}}, {"heights", rows}};
  for (const json& vehicle : {json{{"initial", {{"position", {1, 0, 0}}}}},
                              json{{"kind", "wheel"}, {"initial", {{"position", {1, 0, 0}}}}}}) {
    json d = {{"ground", ground}, {"vehicle", vehicle}, {"duration", 1.0}};
    const Scene scene = buildScene(parseScenario(d));
    Simulator sim(scene.built.model, scene.built.initial);
    ASSERT_TRUE(sim.step(2000)) << vehicle.dump();
    // sitting on the surface, not through it: the body centre is above it
    const Vec3 c = bodyPos(sim.state().y, 0);
    Vec3 grad;
    EXPECT_GT(scene.built.model->ground->eval(c, &grad), 0.0) << vehicle.dump();
    EXPECT_TRUE(sim.healthy());
  }
}

TEST(TerrainFriction, PatchesAndMapsFromTheDocument) {
  json ground = {{"type", "plane"},
                 {"friction_patches",
                  {{{"name", "rink"}, {"circle", {10, 0, 3}}, {"surface", "ice"}},
                   {{"region", {-5, -5, 5, 5}}, {"mu", 0.3}},
                   {{"region", {-1, -1, 1, 1}}, {"surface", "snow"}}}},
                 {"friction_map", {{"cell_size", 10}, {"origin", {-50, -50}}, {"values", {{0.6, 0.6}, {0.8, 0.8}}}}}};
  const Scene scene = buildScene(parseScenario(docWithGround(ground)));
  const Ground& g = *scene.built.model->ground;
  EXPECT_DOUBLE_EQ(g.friction(Vec3(10, 1, 0), 0.5), 0.1);    // ice
  EXPECT_DOUBLE_EQ(g.friction(Vec3(3, 3, 0), 0.5), 0.3);     // the rectangle
  EXPECT_DOUBLE_EQ(g.friction(Vec3(0, 0, 0), 0.5), 0.25);    // snow, listed later, wins
  EXPECT_NEAR(g.friction(Vec3(-45, -45, 0), 0.5), 0.7, 1e-6);  // the map, bilinear
  EXPECT_DOUBLE_EQ(g.friction(Vec3(100, 0, 0), 0.5), 0.5);   // nothing there: the scene's
  const FileAccess none = FileAccess::none();
  auto bad = [&](json patch, const std::string& path, const std::string& why) {
    json gr = {{"type", "plane"}, {"friction_patches", {patch}}};
    EXPECT_TRUE(hasIssue(issuesOf(docWithGround(gr), none), path, why)) << patch.dump();
  };
  bad({{"region", {1, 0, 0, 1}}, {"mu", 0.3}}, "/ground/friction_patches/0/region", "x0 < x1");
  bad({{"region", {0, 0, 1, 1}}, {"circle", {0, 0, 1}}, {"mu", 0.3}}, "/ground/friction_patches/0/circle", "not both");
  bad({{"circle", {0, 0, -1}}, {"mu", 0.3}}, "/ground/friction_patches/0/circle", "radius > 0");
  bad({{"region", {0, 0, 1, 1}}}, "/ground/friction_patches/0/mu", "missing required key");
  bad({{"region", {0, 0, 1, 1}}, {"surface", "lava"}}, "/ground/friction_patches/0/surface", "asphalt");
  bad({{"region", {0, 0, 1, 1}}, {"mu", -0.1}}, "/ground/friction_patches/0/mu", "must be");
  bad({{"region", {0, 0, 1, 1}}, {"mu", 0.2}, {"surface", "ice"}}, "/ground/friction_patches/0/surface", "not both");
  json map = {{"type", "plane"}, {"friction_map", {{"cell_size", 1}, {"values", {{0.5, -0.5}, {0.5, 0.5}}}}}};
  EXPECT_TRUE(hasIssue(issuesOf(docWithGround(map), none), "/ground/friction_map/values", "mu must be >= 0, got -0.5 at row 0, column 1"));
}

TEST(TerrainScenes, ShippedHillsScenarioLoadsItsPngAndRuns) {
  const Scenario s = loadScenarioFile(std::string(GROUNDSIM_SOURCE_DIR) + "/configs/hills.json");
  ASSERT_TRUE(s.ground.heightfield);
  EXPECT_EQ(s.ground.heightfield->nx(), 257);
  EXPECT_EQ(s.ground.heightfield->ny(), 257);
  // 0 to 8 m of hills: make_terrain.py's waves span [0, 1] of full scale
  EXPECT_NEAR(s.ground.heightfield->height(0, 0), 8.0 * (0.5 + 0.15 * std::cos(2 * kPiForHills * 128 / 256 * 2 + 0.7) *
                                                                 std::sin(2 * kPiForHills * 128 / 256 * 2 + 0.3)),
              1e-3);
  const Scene scene = buildScene(s);
  Simulator sim(scene.built.model, scene.built.initial);
  ASSERT_TRUE(sim.step(20000));
  EXPECT_GT(bodyVel(sim.state().y, 0).x(), 0.0);  // driving off along +x
}
