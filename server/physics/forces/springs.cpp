// Report eqs. (1), (13), (14): tension S (|Xj - Xk| - R0) + D d/dt |Xj - Xk|
// along the line between the points. The dashpot acts on the rate of change
// of length (eq. 1); eq. 13's |Uj - Uk| would push points apart whatever
// their relative motion.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "physics/base/pointwise.hpp"
#include "physics/forces/forces.hpp"
#include "physics/simd/simd_path.hpp"

namespace groundsim {
namespace {

GROUNDSIM_INLINE_BODY double sqrtOf(double x) { return std::sqrt(x); }
GROUNDSIM_INLINE_BODY auto sqrtOf(double __attribute__((vector_size(32))) x) {
  return decltype(x){std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
}

// A fan: springs from consecutive points a0 + i to one point b (a wheel rim
// to an axle point). Four springs at a time with GCC vector extensions (AVX2
// where the CPU has it, two SSE2 halves otherwise), the remainder one by one
// through the same formula.
using v4d = double __attribute__((vector_size(32)));

GROUNDSIM_INLINE_BODY v4d load4(const double* p) {
  v4d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
GROUNDSIM_INLINE_BODY void store4(double* p, v4d v) { std::memcpy(p, &v, sizeof v); }

template <class T>
GROUNDSIM_INLINE_BODY T fanTension(T dx, T dy, T dz, T ex, T ey, T ez, T k, T c, T rest, T* inv_out) {
  const T len2 = dx * dx + dy * dy + dz * dz;
  // coincident points: the tiny floor keeps 1/len finite and d = 0 makes the
  // force zero, without a branch
  const T inv = 1.0 / sqrtOf(len2 + 1e-300);
  *inv_out = inv;
  return pointwise::springTension(len2, inv, dx * ex + dy * ey + dz * ez, k, c, rest);
}

GROUNDSIM_INLINE_BODY void fanBody(const Model& m, const Model::SpringFan& fan, Workspace& ws) {
  const int a0 = fan.a0, s0 = fan.first, b = fan.b, n = fan.count;
  double* px = ws.px.data() + a0; double* py = ws.py.data() + a0; double* pz = ws.pz.data() + a0;
  double* ux = ws.ux.data() + a0; double* uy = ws.uy.data() + a0; double* uz = ws.uz.data() + a0;
  double* fx = ws.fx.data() + a0; double* fy = ws.fy.data() + a0; double* fz = ws.fz.data() + a0;
  const double* k = m.spring_k.data() + s0;
  const double* c = m.spring_c.data() + s0;
  const double* rest = m.spring_rest.data() + s0;
  const double bx = ws.px[b], by = ws.py[b], bz = ws.pz[b];
  const double vx = ws.ux[b], vy = ws.uy[b], vz = ws.uz[b];
  v4d Fx = {0, 0, 0, 0}, Fy = Fx, Fz = Fx;
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    const v4d dx = bx - load4(px + i), dy = by - load4(py + i), dz = bz - load4(pz + i);
    const v4d ex = vx - load4(ux + i), ey = vy - load4(uy + i), ez = vz - load4(uz + i);
    v4d inv;
    const v4d t = fanTension(dx, dy, dz, ex, ey, ez, load4(k + i), load4(c + i), load4(rest + i), &inv);
    store4(fx + i, load4(fx + i) + t * dx);
    store4(fy + i, load4(fy + i) + t * dy);
    store4(fz + i, load4(fz + i) + t * dz);
    Fx -= t * dx;
    Fy -= t * dy;
    Fz -= t * dz;
  }
  double sx = Fx[0] + Fx[1] + Fx[2] + Fx[3], sy = Fy[0] + Fy[1] + Fy[2] + Fy[3],
         sz = Fz[0] + Fz[1] + Fz[2] + Fz[3];
  for (; i < n; ++i) {
    const double dx = bx - px[i], dy = by - py[i], dz = bz - pz[i];
    double inv;
    const double t = fanTension(dx, dy, dz, vx - ux[i], vy - uy[i], vz - uz[i], k[i], c[i], rest[i], &inv);
    fx[i] += t * dx;
    fy[i] += t * dy;
    fz[i] += t * dz;
    sx -= t * dx;
    sy -= t * dy;
    sz -= t * dz;
  }
  ws.fx[b] += sx;
  ws.fy[b] += sy;
  ws.fz[b] += sz;
}

GROUNDSIM_WIDE void fansWide(const Model& m, Workspace& ws) {
  for (const Model::SpringFan& fan : m.spring_fans) fanBody(m, fan, ws);
}
void fansGeneric(const Model& m, Workspace& ws) {
  for (const Model::SpringFan& fan : m.spring_fans) fanBody(m, fan, ws);
}

void applyOne(const Spring& s, Workspace& ws) {
  const int a = s.a, b = s.b;
  const double dx = ws.px[b] - ws.px[a], dy = ws.py[b] - ws.py[a], dz = ws.pz[b] - ws.pz[a];
  const double ex = ws.ux[b] - ws.ux[a], ey = ws.uy[b] - ws.uy[a], ez = ws.uz[b] - ws.uz[a];
  double gx, gy, gz;  // force on a; b gets the opposite
  if (s.isotropic) {
    gx = s.stiffness * dx + s.damping * ex;
    gy = s.stiffness * dy + s.damping * ey;
    gz = s.stiffness * dz + s.damping * ez;
  } else {
    // zero length has no direction: only isotropic springs rest there
    const double len2 = dx * dx + dy * dy + dz * dz;
    const double inv = 1.0 / std::sqrt(len2 + 1e-300);
    const double t = pointwise::springTension(len2, inv, dx * ex + dy * ey + dz * ez, s.stiffness, s.damping,
                                              s.rest_length);
    gx = t * dx;
    gy = t * dy;
    gz = t * dz;
  }
  ws.fx[a] += gx;
  ws.fy[a] += gy;
  ws.fz[a] += gz;
  ws.fx[b] -= gx;
  ws.fy[b] -= gy;
  ws.fz[b] -= gz;
}

}  // namespace

void applySprings(const Model& m, Workspace& ws) {
  std::fill(ws.fx.begin(), ws.fx.end(), 0.0);
  std::fill(ws.fy.begin(), ws.fy.end(), 0.0);
  std::fill(ws.fz.begin(), ws.fz.end(), 0.0);
  if (useWideSimd(m.opt.deterministic)) fansWide(m, ws);
  else fansGeneric(m, ws);
  for (int s : m.loose_springs) applyOne(m.springs[s], ws);
}

}  // namespace groundsim
