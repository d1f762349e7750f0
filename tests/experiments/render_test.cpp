// Frames of an environment (render/frame.hpp through BatchEnv::render): the
// sky's colour where nothing is drawn, the car's in the middle, the same
// bytes for the same state, and sizes out of range refused.
#include <gtest/gtest.h>

#include <cstdio>

#include "physics/simulator.hpp"
#include "render/frame.hpp"
#include "render/raster.hpp"
#include "scenario/scenario.hpp"
#include "task_util.hpp"

namespace groundsim::experiments::test {
namespace {

nlohmann::json task() { return {{"observation", {"position"}}}; }

TEST(Render, SkyAboveTheCarInTheMiddleAndTheSameBytesForTheSameState) {
  Batch b(roadCarDoc(plane(), task()), 2);
  b.reset(0);
  const int w = 128, h = 96;
  std::vector<std::uint8_t> f(static_cast<size_t>(w * h * 3)), g(f.size());
  b.env->render(0, w, h, f.data());
  b.env->render(0, w, h, g.data());
  EXPECT_EQ(f, g);
  // the top left pixel: the page's sky, 0x9fc4e0
  EXPECT_EQ((std::vector<int>{f[0], f[1], f[2]}), (std::vector<int>{0x9f, 0xc4, 0xe0}));
  // the sedan (the first vehicle: the page's red, 0xd94f3d, lit) fills the middle
  const size_t mid = (static_cast<size_t>(h / 2 + 10) * w + w / 2) * 3;
  EXPECT_GT(f[mid], f[mid + 1] + 40);
  EXPECT_GT(f[mid], f[mid + 2] + 40);
  // another env in the same state renders the same frame; a step changes it
  b.env->render(1, w, h, g.data());
  EXPECT_EQ(f, g);
  b.setAll({1.0f, 0.0f, 0.5f});
  for (int k = 0; k < 20; ++k) b.step();
  b.env->render(0, w, h, g.data());
  EXPECT_NE(f, g);
}

// On a level plane the patch is drawn row by row (FrameCache::level,
// Raster::levelGround), on another plane as its two corner triangles
// (FrameCache::planar): the grid comes from each pixel's world x and y, so
// each frame is the one the patch's cells draw, but for a few pixels that
// round differently at the lines' and the patch's edges.
TEST(Render, APlaneDrawnAsTwoTrianglesOrByRowsIsTheGridsFrame) {
  const scenario::Scene scene = scenario::buildScene(scenario::parseScenario(roadCarDoc(plane(), task())));
  Simulator sim(scene.built.model, scene.built.initial);
  for (int k = 0; k < 10; ++k) sim.step();
  GroundProbe probe(*sim.model().ground);
  const int w = 128, h = 96;
  render::Raster raster(w, h);
  render::FrameCache cache;
  const size_t size = static_cast<size_t>(w * h * 3);
  std::vector<std::uint8_t> rows(size), planar(size), grid(size);
  render::renderFrame(sim.model(), sim.state(), probe, 0, render::FrameOptions{}, raster, cache, rows.data());
  ASSERT_TRUE(cache.planar && cache.level);
  // the same patch (the cache is kept: the camera did not move), drawn as two triangles, then cell by cell
  cache.level = false;
  render::renderFrame(sim.model(), sim.state(), probe, 0, render::FrameOptions{}, raster, cache, planar.data());
  cache.planar = false;
  render::renderFrame(sim.model(), sim.state(), probe, 0, render::FrameOptions{}, raster, cache, grid.data());
  for (const auto* drawn : {&rows, &planar}) {
    int differ = 0, most = 0;
    for (size_t k = 0; k < size; ++k) {
      const int d = std::abs(static_cast<int>((*drawn)[k]) - static_cast<int>(grid[k]));
      differ += d > 0;
      most = std::max(most, d);
    }
    std::printf("%s: %d of %zu bytes differ from the cells', by %d at most\n", drawn == &rows ? "rows" : "two triangles",
                differ, size, most);
    EXPECT_LE(differ, static_cast<int>(size / 100));
    EXPECT_LE(most, 8);
  }
  EXPECT_NE(rows, std::vector<std::uint8_t>(size, rows[0]));  // a frame, not one colour
}

// Spans four pixels at a time (AVX2, where the CPU has it) give the bytes
// of the pixel-by-pixel loop: the ground's grid, the fog, the car, on a
// plane (two triangles) and on rolling ground (its cells), at sizes whose
// rows end in a part of four.
TEST(Render, WideSpansGiveThePixelLoopsBytes) {
  const nlohmann::json rolling = {{"type", "expression"}, {"expression", "z - 0.3*sin(0.4*x)*cos(0.3*y)"}};
  for (const nlohmann::json& ground : {plane(), rolling}) {
    const scenario::Scene scene = scenario::buildScene(scenario::parseScenario(roadCarDoc(ground, task())));
    Simulator sim(scene.built.model, scene.built.initial);
    GroundProbe probe(*sim.model().ground);
    for (const auto [w, h] : {std::pair{128, 96}, std::pair{67, 41}, std::pair{161, 121}}) {
      for (int k = 0; k < 25; ++k) sim.step();
      render::Raster wide(w, h), one(w, h);
      one.setWideSpans(false);
      render::FrameCache wide_cache, one_cache;
      std::vector<std::uint8_t> a(static_cast<size_t>(w * h * 3)), b(a.size());
      render::renderFrame(sim.model(), sim.state(), probe, 0, render::FrameOptions{}, wide, wide_cache, a.data());
      render::renderFrame(sim.model(), sim.state(), probe, 0, render::FrameOptions{}, one, one_cache, b.data());
      EXPECT_EQ(a, b) << ground.dump() << " at " << w << "x" << h;
    }
  }
}

TEST(Render, SizesOutOfRangeAreRefused) {
  Batch b(roadCarDoc(plane(), task()), 1);
  b.reset(0);
  std::vector<std::uint8_t> f(16 * 16 * 3);
  for (auto [w, h] : {std::pair{8, 16}, std::pair{16, 5000}}) {
    try {
      b.env->render(0, w, h, f.data());
      ADD_FAILURE() << w << " x " << h << " accepted";
    } catch (const ExperimentError& e) {
      EXPECT_EQ(e.field(), "render_size");
    }
  }
  try {
    b.env->render(1, 16, 16, f.data());
    ADD_FAILURE() << "env 1 of 1 accepted";
  } catch (const ExperimentError& e) {
    EXPECT_EQ(e.field(), "env");
  }
}

}  // namespace
}  // namespace groundsim::experiments::test
