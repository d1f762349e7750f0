// Off-screen frames of a scene: a chase camera behind a body, the ground
// as the page draws it (grass with its 1 m grid, sky, fog), and every body
// and object by its collision shapes in the page's colours (vehicle i in
// the i-th colour of web/src/main.js, tyres dark, cones orange). The same
// model and state give the same bytes.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "physics/core/model.hpp"
#include "physics/core/state.hpp"
#include "physics/ground/ground.hpp"
#include "render/raster.hpp"

namespace groundsim::render {

// The frame's size and field of view are the raster's (raster.hpp).
struct FrameOptions {
  double behind = 7.0, above = 2.5;  // m   the camera, from the followed body along its heading
  double ground_extent = 48.0;     // m   side of the ground patch drawn around the camera's target
  double ground_step = 2.0;        // m   its sampling (the grid lines come from each pixel's x, y)
};


// What one scene keeps between its frames: the ground patch last sampled
// (the ground does not move: it is sampled again only when the patch's
// cell origin moves). A frame does not depend on what is in here, only its
// cost does. The raster (its depth buffer, a frame's size) belongs to the
// caller, one for any number of scenes drawn in turn; the frame's bytes are
// drawn straight into the caller's rgb.
// A triangle of a shape in the shape's frame, with its normal pointing out of
// the convex part it bounds (a box, a cylinder, one of a capsule's spheres):
// a triangle whose outward normal faces away from the eye is hidden by its
// part's own front (back-face culling), and is not drawn.
struct Tri {
  std::array<Vec3, 3> v;
  Vec3 out;
};
struct FrameCache {
  double x0 = 0.0, y0 = 0.0, step = 0.0;
  int n = 0;
  std::vector<Vec3> ground;
  std::vector<unsigned char> found;
  // the patch lies in one plane (a plane ground, every point found): drawn
  // as its two corner triangles, its grid from each pixel's world x and y
  bool planar = false;
  // ... and that plane is level (z = height): drawn row by row
  // (Raster::levelGround), a row at one depth
  bool level = false;
  std::vector<Vec3> camera;               // the patch's vertices in this frame's camera coordinates
  std::vector<Shape> shape_of;            // each collider's shape as its triangles were made
  std::vector<std::vector<Tri>> shapes;   // each collider's triangles in its own frame
};

// Writes raster.height() x raster.width() x 3 bytes (RGB, the top row
// first) into rgb. `follow`: the body the camera chases (its heading on the
// ground plane).
void renderFrame(const Model& m, const State& s, GroundProbe& ground, int follow, const FrameOptions& o,
                 Raster& raster, FrameCache& cache, std::uint8_t* rgb);

}  // namespace groundsim::render
