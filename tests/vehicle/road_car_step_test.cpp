// The road car's faster evaluation (bench/results/2026-12-01-performance-history.md, "Issue 12: the
// sedan") against the arithmetic it replaced: the body-frame inverse of the
// reduced mass matrix against the world-frame matrix and its LLT, the four
// tyres at once against tyreForces, libmvec's functions against libm's.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

#include "physics/simd/simd_path.hpp"
#include "physics/road_car/tyre.hpp"
#include "physics/simd/vector_math.hpp"
#include "sedan.hpp"

namespace groundsim::test {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// ulps between two finite doubles of the same sign (or both near 0)
int64_t ulps(double a, double b) {
  int64_t ia, ib;
  std::memcpy(&ia, &a, 8);
  std::memcpy(&ib, &b, 8);
  if (ia < 0) ia = INT64_MIN - ia;
  if (ib < 0) ib = INT64_MIN - ib;
  return ia > ib ? ia - ib : ib - ia;
}

TEST(RoadCarStep, TheBodyFrameInverseSolvesTheWorldMassMatrixAtAnyTravelAndAttitude) {
  for (const RoadCarParams& p : {sedan(), hatch()}) {
    const CarSim cs = makeCar(p, carOptions());
    const RoadCar& rc = cs.car();
    const Body& body = cs.sim->model().bodies[static_cast<size_t>(rc.body)];
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 50; ++trial) {
      const Mat3 R = Quat(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
      const Vec3 nb = R.col(2);
      // road_cars.cpp's world-frame matrix as it was built each evaluation
      Mat6 M = Mat6::Zero();
      M.topLeftCorner<3, 3>() = body.mass * Mat3::Identity();
      M.bottomRightCorner<3, 3>() = R * body.inertia * R.transpose();
      for (int w = 0; w < 4; ++w) {
        const Vec3 r_hub = R * rc.hub[w] + 0.1 * u(rng) * nb;  // any travel
        Vec6 j;
        j << nb, r_hub.cross(nb);
        M -= p.wheel_mass * j * j.transpose();
      }
      Vec6 G;
      for (int i = 0; i < 6; ++i) G[i] = 1e4 * u(rng);
      const Vec6 want = M.llt().solve(G);
      Vec6 Gb;
      Gb << R.transpose() * G.head<3>(), R.transpose() * G.tail<3>();
      const Vec6 ab = rc.inv_mass_body * Gb;
      Vec6 got;
      got << R * ab.head<3>(), R * ab.tail<3>();
      EXPECT_LT((got - want).norm(), 1e-12 * want.norm()) << "trial " << trial;
    }
  }
}

TEST(RoadCarStep, FourTyresAtOnceAreTyreForcesToRounding) {
  const CarSim cs = makeCar(sedan(), carOptions());
  const RoadCar& rc = cs.car();
  const bool wide = useWideSimd(cs.sim->model().opt.deterministic);
  int curves = 0;
  for (double Fz : {0.0, 150.0, 3500.0, 9000.0})
    for (double mu : {0.3, 1.0})
      for (double kx : {-0.6, -0.1, -1e-3, 0.0, 2e-12, 0.02, 0.12, 0.9})
        for (double ky : {-0.5, -0.05, 0.0, 1e-3, 0.1, 0.3}) {
          TyreLanes lanes;
          for (int w = 0; w < 4; ++w) {
            lanes.on[w] = w != 3;  // one lane off: 0, 0
            lanes.t[w] = &rc.p.tyre[w < 2 ? 0 : 1];
            lanes.Fz[w] = Fz * (1.0 + 0.1 * w);
            lanes.Fz0[w] = rc.nominal_load[w];
            lanes.inv_Fz0[w] = rc.inv_nominal_load[w];
            lanes.mu[w] = mu;
            lanes.kx[w] = kx * (1.0 - 0.2 * w);
            lanes.ky[w] = ky;
          }
          double fx[4], fy[4], gx[4], gy[4];
          tyreForces4(lanes, wide, fx, fy);
          tyreForces4(lanes, false, gx, gy);
          for (int w = 0; w < 4; ++w) {
            double ex = 0.0, ey = 0.0;
            if (lanes.on[w])
              tyreForces(*lanes.t[w], lanes.Fz[w], lanes.Fz0[w], mu, lanes.kx[w], lanes.ky[w], &ex, &ey);
            // lane by lane: tyreForces bit for bit
            EXPECT_EQ(gx[w], ex);
            EXPECT_EQ(gy[w], ey);
            // four at a time: within rounding of it (a peak of ~1e4 N)
            EXPECT_NEAR(fx[w], ex, 1e-12 * (std::abs(ex) + 1.0)) << Fz << " " << kx << " " << ky << " lane " << w;
            EXPECT_NEAR(fy[w], ey, 1e-12 * (std::abs(ey) + 1.0)) << Fz << " " << kx << " " << ky << " lane " << w;
            curves += ex != 0.0;
          }
        }
  EXPECT_GT(curves, 300);  // the grid reaches the curves, not only the zero lanes
}

TEST(RoadCarStep, VectorMathIsLibmWithinFourUlp) {
  const CarSim cs = makeCar(sedan(), carOptions());
  const bool wide = useWideSimd(cs.sim->model().opt.deterministic);
  if (!wide || !vectorMathAvailable()) GTEST_SKIP() << "no AVX2 or no libmvec: the calls are libm's";
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int64_t worst[3] = {0, 0, 0};
  for (int k = 0; k < 4000; ++k) {
    alignas(32) double x[4], y[4], out[4];
    for (int i = 0; i < 4; ++i) {
      x[i] = std::ldexp(u(rng), static_cast<int>(k % 24) - 12);  // 2^-12 .. 2^12, both signs
      y[i] = u(rng) * 3.0;
    }
    atan4(x, out, true);
    for (int i = 0; i < 4; ++i) worst[0] = std::max(worst[0], ulps(out[i], std::atan(x[i])));
    sin4(y, out, true);  // the Magic Formula's C atan(...): |arg| < pi
    for (int i = 0; i < 4; ++i) worst[1] = std::max(worst[1], ulps(out[i], std::sin(y[i])));
    tanh4(x, out, true);
    for (int i = 0; i < 4; ++i) worst[2] = std::max(worst[2], ulps(out[i], std::tanh(x[i])));
  }
  for (int f = 0; f < 3; ++f) EXPECT_LE(worst[f], 8) << "function " << f;  // 4 ulp each way from the exact value
}

}  // namespace
}  // namespace groundsim::test
