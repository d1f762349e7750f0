#include "render/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "physics/simd/simd_path.hpp"

namespace groundsim::render {
namespace {

constexpr double kNear = 0.05;                   // m  near plane
constexpr double kFogStart = 30.0, kFogEnd = 70.0;  // m  as the page's THREE.Fog
constexpr double kFogScale = 1.0 / (kFogEnd - kFogStart);
const Vec3 kSun = Vec3(0.4, 0.3, 0.85).normalized();

// The page's ground texture (web/src/ground.js): grass with a dark line at
// every metre and a lighter one at every half metre.
constexpr Rgb kGrass{0x6f / 255.0, 0x8f / 255.0, 0x5a / 255.0}, kEdge{0x2f / 255.0, 0x3f / 255.0, 0x28 / 255.0},
    kHalf{0x4d / 255.0, 0x66 / 255.0, 0x40 / 255.0};

// v's fractional part, v - floor(v), for |v| below 2^62 (a ground patch's
// metres): a truncation, not libm's floor (baseline x86-64 has no rounding
// instruction, and this runs for every ground pixel)
double frac(double v) {
  double f = static_cast<double>(static_cast<long long>(v));
  if (f > v) f -= 1.0;
  return v - f;
}

// Which of the texture's colours (kGround) lies at world x, y.
enum GroundColour { kGrassColour, kEdgeColour, kHalfColour };
constexpr std::array<Rgb, 3> kGround{kGrass, kEdge, kHalf};
int groundAt(double x, double y) {
  const double fx = frac(x), fy = frac(y);
  const double edge_w = 3.0 / 256.0, half_w = 1.0 / 256.0;  // the canvas' line widths over its 256 px
  if (fx < edge_w || fx > 1.0 - edge_w || fy < edge_w || fy > 1.0 - edge_w) return kEdgeColour;
  if (std::abs(fx - 0.5) < half_w || std::abs(fy - 0.5) < half_w) return kHalfColour;
  return kGrassColour;
}

std::uint8_t byteOf(double v) { return static_cast<std::uint8_t>(std::clamp(v * 255.0 + 0.5, 0.0, 255.0)); }

// A colour's bytes, made once for a triangle's pixels that are not fogged.
using Bytes = std::array<std::uint8_t, 3>;
Bytes bytesOf(const Rgb& c) { return {byteOf(c.r), byteOf(c.g), byteOf(c.b)}; }

// The ground's three colours (kGround) lit by `light`.
std::array<Rgb, 3> groundLit(double light) {
  std::array<Rgb, 3> lit{};
  for (size_t g = 0; g < lit.size(); ++g) lit[g] = {kGround[g].r * light, kGround[g].g * light, kGround[g].b * light};
  return lit;
}

// c faded towards the sky by the fog's fade f (0: c; 1: the sky).
Rgb fogged(const Rgb& c, double f, const Rgb& sky) {
  return {c.r + f * (sky.r - c.r), c.g + f * (sky.g - c.g), c.b + f * (sky.b - c.b)};
}

// A span four pixels at a time: for pixels i of a row from lo on, 1 /
// depth, the depth test, and for the pixels drawn their colour (Grid: the
// ground's grid at the pixel's world x, y; else the triangle's) faded by
// the fog, written as bytes.
// The same operations in the same order as the scalar loop in Raster::fill
// (an unfogged pixel's fade is 0: col + 0 (sky - col) is col), in AVX2
// without FMA (target "avx2" alone: no multiply-add can be contracted), so
// the bytes are the scalar loop's on every machine; libm is not called
// (floor is a rounding toward zero, as frac's truncation). Returns how many
// pixels it did (a multiple of 4); the rest is the scalar loop's.
struct SpanIn {
  double wa_row, wb_row, dwa_dx, dwb_dx;
  double ainv, binv, cinv, awx, bwx, cwx, awy, bwy, cwy;
  double lit[3][3];  // [channel][kGround index]: the ground's colours lit by the triangle's light (Grid),
                     // else [channel][0]: the triangle's colour
  double sky[3];
};
#if defined(__x86_64__)
#define GROUNDSIM_AVX2 __attribute__((target("avx2"), always_inline)) inline
// v - floor(v) as frac() computes it: truncated, one less where that is above v
GROUNDSIM_AVX2 __m256d frac4(__m256d v) {
  const __m256d f = _mm256_round_pd(v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
  return _mm256_sub_pd(v, _mm256_blendv_pd(f, _mm256_sub_pd(f, _mm256_set1_pd(1.0)), _mm256_cmp_pd(f, v, _CMP_GT_OQ)));
}
// wa a + wb b + wc c, summed left to right
GROUNDSIM_AVX2 __m256d interp(__m256d wa, __m256d wb, __m256d wc, double a, double b, double c) {
  return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(wa, _mm256_set1_pd(a)), _mm256_mul_pd(wb, _mm256_set1_pd(b))),
                       _mm256_mul_pd(wc, _mm256_set1_pd(c)));
}
// a channel's byte, as byteOf: (v 255 + 0.5) clamped to [0, 255], truncated
GROUNDSIM_AVX2 __m128i bytes4(__m256d v) {
  const __m256d x = _mm256_add_pd(_mm256_mul_pd(v, _mm256_set1_pd(255.0)), _mm256_set1_pd(0.5));
  return _mm256_cvttpd_epi32(_mm256_min_pd(_mm256_max_pd(x, _mm256_setzero_pd()), _mm256_set1_pd(255.0)));
}
template <bool Grid>
__attribute__((target("avx2"))) int spanQuads(const SpanIn& in, int lo, int hi, double* depth, std::uint8_t* rgb) {
  const int n = (hi - lo + 1) / 4 * 4;
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
  const __m256d lane = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
  const __m256d sign = _mm256_set1_pd(-0.0);
  const double edge_w = 3.0 / 256.0, half_w = 1.0 / 256.0;
  const __m256d ew = _mm256_set1_pd(edge_w), ew_hi = _mm256_set1_pd(1.0 - edge_w), hw = _mm256_set1_pd(half_w);
  const __m256d half = _mm256_set1_pd(0.5), fog_start = _mm256_set1_pd(kFogStart), fog_scale = _mm256_set1_pd(kFogScale);
  const __m256d fog_start_inv = _mm256_set1_pd(1.0 / kFogStart);
  // r0 r1 r2 r3 g0 .. b3 (packed) to r0 g0 b0 r1 g1 b1 ... (the buffer's order)
  const __m128i interleave = _mm_setr_epi8(0, 4, 8, 1, 5, 9, 2, 6, 10, 3, 7, 11, 12, 13, 14, 15);
  for (int q = 0; q < n; q += 4) {
    const int i = lo + q;
    const __m256d di = _mm256_add_pd(_mm256_set1_pd(static_cast<double>(i)), lane);
    const __m256d wa =
        _mm256_max_pd(_mm256_add_pd(_mm256_set1_pd(in.wa_row), _mm256_mul_pd(_mm256_set1_pd(in.dwa_dx), di)), zero);
    const __m256d wb =
        _mm256_max_pd(_mm256_add_pd(_mm256_set1_pd(in.wb_row), _mm256_mul_pd(_mm256_set1_pd(in.dwb_dx), di)), zero);
    const __m256d wc = _mm256_max_pd(_mm256_sub_pd(_mm256_sub_pd(one, wa), wb), zero);
    const __m256d inv_z = interp(wa, wb, wc, in.ainv, in.binv, in.cinv);
    double* d = depth + i;
    const __m256d old = _mm256_loadu_pd(d);
    const __m256d nearer = _mm256_cmp_pd(inv_z, old, _CMP_GT_OQ);
    const int drawn = _mm256_movemask_pd(nearer);
    if (drawn == 0) continue;
    _mm256_storeu_pd(d, _mm256_blendv_pd(old, inv_z, nearer));
    const __m256d z = _mm256_div_pd(one, inv_z);
    __m256d edge = zero, halfline = zero;
    if constexpr (Grid) {
      const __m256d fx = frac4(_mm256_mul_pd(interp(wa, wb, wc, in.awx, in.bwx, in.cwx), z));
      const __m256d fy = frac4(_mm256_mul_pd(interp(wa, wb, wc, in.awy, in.bwy, in.cwy), z));
      edge = _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(fx, ew, _CMP_LT_OQ), _mm256_cmp_pd(fx, ew_hi, _CMP_GT_OQ)),
                          _mm256_or_pd(_mm256_cmp_pd(fy, ew, _CMP_LT_OQ), _mm256_cmp_pd(fy, ew_hi, _CMP_GT_OQ)));
      halfline = _mm256_or_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, _mm256_sub_pd(fx, half)), hw, _CMP_LT_OQ),
                              _mm256_cmp_pd(_mm256_andnot_pd(sign, _mm256_sub_pd(fy, half)), hw, _CMP_LT_OQ));
    }
    // the fog's fade: 0 up to its start (a triangle's own colour also where
    // 1 / depth is at least the start's, as the scalar loop decides first),
    // then (z - start) / its length up to 1
    __m256d unfogged = _mm256_cmp_pd(z, fog_start, _CMP_LE_OQ);
    if constexpr (!Grid) unfogged = _mm256_or_pd(unfogged, _mm256_cmp_pd(inv_z, fog_start_inv, _CMP_GE_OQ));
    const __m256d fade =
        _mm256_blendv_pd(_mm256_min_pd(_mm256_mul_pd(_mm256_sub_pd(z, fog_start), fog_scale), one), zero, unfogged);
    __m128i ch[3];
    for (int c = 0; c < 3; ++c) {
      // the grid's colour: an edge line, else a half-metre line, else grass
      const __m256d col =
          Grid ? _mm256_blendv_pd(_mm256_blendv_pd(_mm256_set1_pd(in.lit[c][kGrassColour]),
                                                   _mm256_set1_pd(in.lit[c][kHalfColour]), halfline),
                                  _mm256_set1_pd(in.lit[c][kEdgeColour]), edge)
               : _mm256_set1_pd(in.lit[c][0]);
      const __m256d v = _mm256_add_pd(col, _mm256_mul_pd(fade, _mm256_sub_pd(_mm256_set1_pd(in.sky[c]), col)));
      ch[c] = bytes4(v);
    }
    // the four pixels' bytes in the buffer's order (each value is in [0, 255]: the packs do not saturate)
    alignas(16) std::uint8_t px[16];
    _mm_store_si128(reinterpret_cast<__m128i*>(px),
                    _mm_shuffle_epi8(_mm_packus_epi16(_mm_packus_epi32(ch[0], ch[1]), _mm_packus_epi32(ch[2], ch[2])),
                                     interleave));
    std::uint8_t* p = rgb + 3 * static_cast<size_t>(i);
    if (drawn == 0xf) {
      std::memcpy(p, px, 12);
      continue;
    }
    for (int k = 0; k < 4; ++k)
      if ((drawn >> k) & 1) std::memcpy(p + 3 * k, px + 3 * k, 3);
  }
  return n;
}
// For each set of a quad's pixels (bit k: pixel k), a byte mask over their
// three bytes each: laneBytes(m) selects those pixels' bytes.
struct LaneBytes {
  alignas(16) std::uint8_t mask[16][16];
  constexpr LaneBytes() : mask{} {
    for (int m = 0; m < 16; ++m)
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) mask[m][3 * k + c] = (m >> k) & 1 ? 0xff : 0;
  }
};
constexpr LaneBytes kLaneMasks;
GROUNDSIM_AVX2 __m128i laneBytes(int m) { return _mm_load_si128(reinterpret_cast<const __m128i*>(kLaneMasks.mask[m])); }

// A row of a level ground four pixels at a time (Raster::levelGround): the
// grid's colour of pixels i from lo on at world x = xa + xb i, y = ya + yb i
// (a multiply then an add, as the scalar loop), its bytes taken from the
// row's three. Returns how many pixels it did (a multiple of 4).
__attribute__((target("avx2"))) int levelQuads(double xa, double xb, double ya, double yb, const Bytes* bytes, int lo,
                                               int hi, std::uint8_t* rgb) {
  const int n = (hi - lo + 1) / 4 * 4;
  const __m256d lane = _mm256_set_pd(3.0, 2.0, 1.0, 0.0);
  const __m256d sign = _mm256_set1_pd(-0.0), half = _mm256_set1_pd(0.5);
  const double edge_w = 3.0 / 256.0, half_w = 1.0 / 256.0;
  const __m256d ew = _mm256_set1_pd(edge_w), ew_hi = _mm256_set1_pd(1.0 - edge_w), hw = _mm256_set1_pd(half_w);
  const __m256d vxa = _mm256_set1_pd(xa), vxb = _mm256_set1_pd(xb), vya = _mm256_set1_pd(ya), vyb = _mm256_set1_pd(yb);
  // a colour's bytes four times over, in a pixel quad's 12 bytes
  const auto quad = [](const Bytes& b) {
    return _mm_setr_epi8(b[0], b[1], b[2], b[0], b[1], b[2], b[0], b[1], b[2], b[0], b[1], b[2], 0, 0, 0, 0);
  };
  const __m128i grass = quad(bytes[kGrassColour]), halfc = quad(bytes[kHalfColour]), edgec = quad(bytes[kEdgeColour]);
  for (int q = 0; q < n; q += 4) {
    const int i = lo + q;
    const __m256d di = _mm256_add_pd(_mm256_set1_pd(static_cast<double>(i)), lane);
    const __m256d fx = frac4(_mm256_add_pd(vxa, _mm256_mul_pd(vxb, di)));
    const __m256d fy = frac4(_mm256_add_pd(vya, _mm256_mul_pd(vyb, di)));
    const int edge = _mm256_movemask_pd(
        _mm256_or_pd(_mm256_or_pd(_mm256_cmp_pd(fx, ew, _CMP_LT_OQ), _mm256_cmp_pd(fx, ew_hi, _CMP_GT_OQ)),
                     _mm256_or_pd(_mm256_cmp_pd(fy, ew, _CMP_LT_OQ), _mm256_cmp_pd(fy, ew_hi, _CMP_GT_OQ))));
    const int halfline =
        _mm256_movemask_pd(_mm256_or_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, _mm256_sub_pd(fx, half)), hw, _CMP_LT_OQ),
                                        _mm256_cmp_pd(_mm256_andnot_pd(sign, _mm256_sub_pd(fy, half)), hw, _CMP_LT_OQ)));
    // grass, where a half-metre line then an edge line over it (groundAt's order)
    const __m128i px = _mm_blendv_epi8(_mm_blendv_epi8(grass, halfc, laneBytes(halfline)), edgec, laneBytes(edge));
    alignas(16) std::uint8_t out[16];
    _mm_store_si128(reinterpret_cast<__m128i*>(out), px);
    std::memcpy(rgb + 3 * static_cast<size_t>(i), out, 12);
  }
  return n;
}
#endif

}  // namespace

Rgb rgbOf(std::uint32_t hex) {
  return {((hex >> 16) & 0xff) / 255.0, ((hex >> 8) & 0xff) / 255.0, (hex & 0xff) / 255.0};
}

Raster::Raster(int width, int height, double fov_deg)
    : width_(width), height_(height),
      focal_(0.5 * height / std::tan(0.5 * fov_deg * std::acos(-1.0) / 180.0)),
      depth_(static_cast<size_t>(width) * height), wide_(useWideSimd(false)) {}

void Raster::look(const Vec3& eye, const Vec3& target) {
  eye_ = eye;
  forward_ = (target - eye).normalized();
  Vec3 r = forward_.cross(Vec3::UnitZ());
  if (r.norm() < 1e-9) r = Vec3::UnitX();  // looking straight down or up
  right_ = r.normalized();
  up_ = right_.cross(forward_);
}

void Raster::clear(const Rgb& sky, std::uint8_t* rgb) {
  sky_ = sky;
  colour_ = rgb;
  const std::uint8_t r = byteOf(sky.r), g = byteOf(sky.g), b = byteOf(sky.b);
  std::fill(depth_.begin(), depth_.end(), 0.0);  // 1 / depth: nothing drawn is infinitely far
  // the first pixel, then the filled part copied onto the rest, doubling
  const size_t size = depth_.size() * 3;
  if (size == 0) return;
  colour_[0] = r, colour_[1] = g, colour_[2] = b;
  for (size_t done = 3; done < size; done *= 2) std::memcpy(colour_ + done, colour_, std::min(done, size - done));
}

Raster::Vertex Raster::project(const Vec3& cam, const Vec3& world) const {
  const double inv = 1.0 / cam.z();
  return {0.5 * width_ + focal_ * cam.x() * inv, 0.5 * height_ - focal_ * cam.y() * inv, inv, world.x() * inv,
          world.y() * inv};
}

void Raster::triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Rgb& colour, bool grid) {
  const Vec3 ca = toCamera(a), cb = toCamera(b), cc = toCamera(c);
  if (outside(ca, cb, cc)) return;
  triangle(a, b, c, ca, cb, cc, colour, grid);
}

bool Raster::outside(const Vec3& a, const Vec3& b, const Vec3& c) const {
  if (a.z() < kNear && b.z() < kNear && c.z() < kNear) return true;
  // the frame's sides through the eye: x = +-(w/2) z / focal, y = +-(h/2) z / focal (a pixel of margin)
  const double sx = (0.5 * width_ + 1.0) / focal_, sy = (0.5 * height_ + 1.0) / focal_;
  auto beyond = [](double u, double z, double slope) { return u > slope * z; };
  if (beyond(a.x(), a.z(), sx) && beyond(b.x(), b.z(), sx) && beyond(c.x(), c.z(), sx)) return true;
  if (beyond(-a.x(), a.z(), sx) && beyond(-b.x(), b.z(), sx) && beyond(-c.x(), c.z(), sx)) return true;
  if (beyond(a.y(), a.z(), sy) && beyond(b.y(), b.z(), sy) && beyond(c.y(), c.z(), sy)) return true;
  if (beyond(-a.y(), a.z(), sy) && beyond(-b.y(), b.z(), sy) && beyond(-c.y(), c.z(), sy)) return true;
  // beyond the fog's end: drawn as sky
  return a.z() > kFogEnd && b.z() > kFogEnd && c.z() > kFogEnd;
}

void Raster::triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& ca, const Vec3& cb, const Vec3& cc,
                      const Rgb& colour, bool grid) {
  // two-sided Lambert light: the normal turned towards the camera
  Vec3 n = (b - a).cross(c - a);
  const double nn = n.norm();
  if (!(nn > 0.0)) return;
  n /= nn;
  if (n.dot(eye_ - a) < 0.0) n = -n;
  const double light = 0.45 + 0.55 * std::max(0.0, n.dot(kSun));
  const Rgb lit{colour.r * light, colour.g * light, colour.b * light};
  // clipped by the near plane (a polygon of up to 4)
  const std::array<Vec3, 3> world = {a, b, c};
  const std::array<Vec3, 3> cam = {ca, cb, cc};
  std::array<Vec3, 4> pc, pw;
  int n_out = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const bool in_i = cam[i].z() >= kNear, in_j = cam[j].z() >= kNear;
    if (in_i) {
      pc[n_out] = cam[i];
      pw[n_out++] = world[i];
    }
    if (in_i != in_j) {
      const double t = (kNear - cam[i].z()) / (cam[j].z() - cam[i].z());
      pc[n_out] = cam[i] + t * (cam[j] - cam[i]);
      pw[n_out++] = world[i] + t * (world[j] - world[i]);
    }
  }
  if (n_out < 3) return;
  const Vertex v0 = project(pc[0], pw[0]);
  for (int i = 1; i + 1 < n_out; ++i) fill(v0, project(pc[i], pw[i]), project(pc[i + 1], pw[i + 1]), lit, grid);
}

void Raster::fill(const Vertex& a, const Vertex& b, const Vertex& c, const Rgb& lit, bool grid) {
  const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(std::abs(area) > 1e-12)) return;
  // the pixels whose centres can be inside: the bounding box's, rounded outwards
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}) - 0.5)));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}) - 0.5)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}) - 0.5)));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}) - 0.5)));
  if (x0 > x1 || y0 > y1) return;
  // barycentric weights from the edge functions, linear in x and y: their
  // values at the box's first pixel centre, then a step per pixel and per row
  const double inv_area = 1.0 / area;
  const double dwa_dx = (b.y - c.y) * inv_area, dwa_dy = (c.x - b.x) * inv_area;
  const double dwb_dx = (c.y - a.y) * inv_area, dwb_dy = (a.x - c.x) * inv_area;
  const double xs = x0 + 0.5, ys = y0 + 0.5;
  double wa_row = ((b.x - xs) * (c.y - ys) - (b.y - ys) * (c.x - xs)) * inv_area;
  double wb_row = ((c.x - xs) * (a.y - ys) - (c.y - ys) * (a.x - xs)) * inv_area;
  constexpr double kFogStartInv = 1.0 / kFogStart;
  const int last = x1 - x0;
  // the unfogged pixels' bytes, made once: the triangle's colour, or the
  // ground's three lit by it (the ground passes white: lit.r is the light)
  const double light = lit.r;
  const Bytes own = bytesOf(lit);
  std::array<Rgb, 3> ground_lit{};
  std::array<Bytes, 3> ground{};
  if (grid) {
    ground_lit = groundLit(light);
    for (size_t g = 0; g < ground.size(); ++g) ground[g] = bytesOf(ground_lit[g]);
  }
  // a drawn ground pixel at depth z showing colour g: its bytes made once
  // unfogged, faded towards the sky past the fog's start
  const auto groundPixel = [&](size_t k, double z, int g) {
    if (z <= kFogStart) return put(k, ground[static_cast<size_t>(g)]);
    const Rgb& col = ground_lit[static_cast<size_t>(g)];
    const double f = std::min((z - kFogStart) * kFogScale, 1.0);
    put(k, fogged(col, f, sky_));
  };
#if defined(__x86_64__)
  SpanIn span;  // every field set here (no zeroing of its 25 doubles per triangle)
  span.dwa_dx = dwa_dx, span.dwb_dx = dwb_dx;
  span.ainv = a.inv_z, span.binv = b.inv_z, span.cinv = c.inv_z;
  span.awx = a.wx, span.bwx = b.wx, span.cwx = c.wx, span.awy = a.wy, span.bwy = b.wy, span.cwy = c.wy;
  if (grid)
    for (size_t g = 0; g < ground_lit.size(); ++g)
      span.lit[0][g] = ground_lit[g].r, span.lit[1][g] = ground_lit[g].g, span.lit[2][g] = ground_lit[g].b;
  else
    span.lit[0][0] = lit.r, span.lit[1][0] = lit.g, span.lit[2][0] = lit.b;  // [c][1], [c][2] unread
  span.sky[0] = sky_.r, span.sky[1] = sky_.g, span.sky[2] = sky_.b;
#endif
  for (int py = y0; py <= y1; ++py, wa_row += dwa_dy, wb_row += dwb_dy) {
    // the row's pixels inside: where each weight w0 + dw i (i from the box's
    // first pixel) is >= 0, intersected; the third weight is 1 - wa - wb
    int lo = 0, hi = last;
    const double wc_row = 1.0 - wa_row - wb_row, dwc_dx = -dwa_dx - dwb_dx;
    for (const auto [w0, dw] : {std::pair{wa_row, dwa_dx}, std::pair{wb_row, dwb_dx}, std::pair{wc_row, dwc_dx}}) {
      if (dw > 0.0) {
        lo = std::max(lo, static_cast<int>(std::ceil(std::clamp(-w0 / dw, -1.0, last + 1.0))));
      } else if (dw < 0.0) {
        hi = std::min(hi, static_cast<int>(std::floor(std::clamp(w0 / -dw, -1.0, last + 1.0))));
      } else if (w0 < 0.0) {
        hi = -1;
      }
    }
    if (lo > hi) continue;
    const size_t row = static_cast<size_t>(py) * width_;
    // the span four pixels at a time where the CPU has AVX2 (the same
    // bytes: spanQuads), then the rest one by one
    int i = lo;
#if defined(__x86_64__)
    if (wide_ && hi - lo >= 3) {  // the same bytes either way
      span.wa_row = wa_row, span.wb_row = wb_row;
      i += (grid ? spanQuads<true> : spanQuads<false>)(span, lo, hi, depth_.data() + row + x0,
                                                       colour_ + 3 * (row + x0));
    }
#endif
    for (; i <= hi; ++i) {
      const int px = x0 + i;
      // at the span's ends a weight may be a rounding below 0: clamped
      const double wa = std::max(0.0, wa_row + dwa_dx * i), wb = std::max(0.0, wb_row + dwb_dx * i);
      const double wc = std::max(0.0, 1.0 - wa - wb);
      // nearer: a larger 1 / depth (the buffer holds 1 / depth; no division for a hidden pixel)
      const double inv_z = wa * a.inv_z + wb * b.inv_z + wc * c.inv_z;
      const size_t k = row + px;
      if (!(inv_z > depth_[k])) continue;
      depth_[k] = inv_z;
      if (!grid && inv_z >= kFogStartInv) {  // unfogged, its own colour: no depth needed
        put(k, own);
        continue;
      }
      const double z = 1.0 / inv_z;
      if (grid) {
        groundPixel(k, z, groundAt((wa * a.wx + wb * b.wx + wc * c.wx) * z, (wa * a.wy + wb * b.wy + wc * c.wy) * z));
        continue;
      }
      if (z <= kFogStart) {
        put(k, own);
        continue;
      }
      const double f = std::min((z - kFogStart) * kFogScale, 1.0);
      put(k, fogged(lit, f, sky_));
    }
  }
}

// The pixels i of a row (from 0 to last) whose coordinate a + b i lies in
// [lo_b, hi_b], intersected with [lo, hi].
static void keepWithin(double a, double b, double lo_b, double hi_b, int last, int& lo, int& hi) {
  if (b == 0.0) {
    if (!(a >= lo_b && a <= hi_b)) hi = -1;
    return;
  }
  double from = (lo_b - a) / b, to = (hi_b - a) / b;
  if (b < 0.0) std::swap(from, to);
  lo = std::max(lo, static_cast<int>(std::ceil(std::clamp(from, -1.0, last + 1.0))));
  hi = std::min(hi, static_cast<int>(std::floor(std::clamp(to, -1.0, last + 1.0))));
}

void Raster::levelGround(double height, double x_lo, double x_hi, double y_lo, double y_hi) {
  // lit as a triangle of it: its normal turned towards the eye
  const double light = 0.45 + 0.55 * std::max(0.0, (eye_.z() >= height ? 1.0 : -1.0) * kSun.z());
  const std::array<Rgb, 3> lit = groundLit(light);
  const double u0 = 0.5 - 0.5 * width_;  // pixel 0's centre from the frame's middle, px
  for (int py = 0; py < height_; ++py) {
    // the row's ray direction eye + t (forward + u right + v up) (right has
    // no z: the row's rays meet the plane at one camera depth t)
    const double v = (0.5 * height_ - (py + 0.5)) / focal_;
    const double t = (height - eye_.z()) / (forward_.z() + v * up_.z());
    if (!(t >= kNear && t <= kFogEnd)) continue;
    const double s = t / focal_;
    const double xa = eye_.x() + t * (forward_.x() + v * up_.x()) + s * u0 * right_.x(), xb = s * right_.x();
    const double ya = eye_.y() + t * (forward_.y() + v * up_.y()) + s * u0 * right_.y(), yb = s * right_.y();
    int lo = 0, hi = width_ - 1;
    keepWithin(xa, xb, x_lo, x_hi, width_ - 1, lo, hi);
    keepWithin(ya, yb, y_lo, y_hi, width_ - 1, lo, hi);
    if (lo > hi) continue;
    // the row's three colours faded by its fog, as bytes
    const double f = t <= kFogStart ? 0.0 : std::min((t - kFogStart) * kFogScale, 1.0);
    std::array<Bytes, 3> bytes{};
    for (size_t g = 0; g < bytes.size(); ++g) bytes[g] = bytesOf(fogged(lit[g], f, sky_));
    const size_t row = static_cast<size_t>(py) * width_;
    std::fill(depth_.begin() + static_cast<std::ptrdiff_t>(row + lo), depth_.begin() + static_cast<std::ptrdiff_t>(row + hi + 1),
              1.0 / t);
    int i = lo;
#if defined(__x86_64__)
    if (wide_) i += levelQuads(xa, xb, ya, yb, bytes.data(), lo, hi, colour_ + 3 * row);
#endif
    for (; i <= hi; ++i) put(row + i, bytes[static_cast<size_t>(groundAt(xa + xb * i, ya + yb * i))]);
  }
}

void Raster::put(size_t k, const Rgb& c) { put(k, bytesOf(c)); }

void Raster::put(size_t k, const std::array<std::uint8_t, 3>& bytes) {
  std::uint8_t* p = colour_ + 3 * k;
  p[0] = bytes[0], p[1] = bytes[1], p[2] = bytes[2];
}


}  // namespace groundsim::render
