#include "physics/ground/heightfield.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace groundsim {
namespace {

// The cubic B-spline's interpolation prefilter (Unser 1991, Thevenaz et al.
// 2000): the coefficients c solve (c[k-1] + 4 c[k] + c[k+1]) / 6 = f[k],
// i.e. f times 6 through a causal and an anticausal first-order recursion
// with pole z = sqrt(3) - 2, the sequence mirrored at both ends.
const double kPole = std::sqrt(3.0) - 2.0;
// |z|^k < 1e-14 beyond this many terms: the causal start is a truncated sum
constexpr int kHorizon = 25;

// Filters n values c[0], c[stride], ... in place (already multiplied by 6).
void prefilter(double* c, int n, std::ptrdiff_t stride) {
  const double z = kPole;
  auto at = [&](int k) -> double& { return c[k * stride]; };
  // causal start: sum of z^k f[mirror(k)] over the mirrored sequence
  double sum;
  if (n > kHorizon) {
    double zn = 1.0;
    sum = 0.0;
    for (int k = 0; k < kHorizon; ++k, zn *= z) sum += zn * at(k);
  } else {  // short: the exact sum over the period 2n - 2 of the mirror
    double zn = z, z2n = std::pow(z, n - 1);
    const double iz = 1.0 / z;
    sum = at(0) + z2n * at(n - 1);
    z2n *= z2n * iz;
    for (int k = 1; k <= n - 2; ++k, zn *= z, z2n *= iz) sum += (zn + z2n) * at(k);
    sum /= 1.0 - zn * zn;
  }
  at(0) = sum;
  for (int k = 1; k < n; ++k) at(k) += z * at(k - 1);
  at(n - 1) = (z / (z * z - 1.0)) * (z * at(n - 2) + at(n - 1));
  for (int k = n - 2; k >= 0; --k) at(k) = z * (at(k + 1) - at(k));
}

// Cubic B-spline weights of the four samples around t in [0, 1], and their
// derivatives with respect to t.
inline void weights(double t, double w[4], double d[4]) {
  const double s = 1.0 - t, t2 = t * t;
  w[0] = s * s * s / 6.0;
  w[1] = (3.0 * t2 * t - 6.0 * t2 + 4.0) / 6.0;
  w[2] = (-3.0 * t2 * t + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
  w[3] = t2 * t / 6.0;
  d[0] = -0.5 * s * s;
  d[1] = 1.5 * t2 - 2.0 * t;
  d[2] = -1.5 * t2 + t + 0.5;
  d[3] = 0.5 * t2;
}

// Grid coordinate u of a position, clamped to [0, n - 1] (clamped: the
// surface is flat in that direction); cell index i in [0, n - 2] and the
// fraction t in [0, 1]; the four mirrored sample indices.
inline bool locate(double u, int n, int idx[4], double* t) {
  bool clamped = false;
  if (!(u > 0.0)) {
    u = 0.0;
    clamped = true;
  } else if (u >= n - 1) {
    u = n - 1;
    clamped = true;
  }
  const int i = std::min(static_cast<int>(u), n - 2);
  *t = u - i;
  idx[0] = i == 0 ? 1 : i - 1;
  idx[1] = i;
  idx[2] = i + 1;
  idx[3] = i + 2 > n - 1 ? n - 2 : i + 2;  // mirror of n is n - 2
  return clamped;
}

}  // namespace

HeightfieldGround::HeightfieldGround(HeightSamples s)
    : nx_(s.nx), ny_(s.ny), cell_(s.cell), x0_(s.x0), y0_(s.y0), coef_(std::move(s.heights)) {
  if (nx_ < 2 || ny_ < 2) throw std::invalid_argument("heightfield: needs at least 2 x 2 samples");
  if (coef_.size() != static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_))
    throw std::invalid_argument("heightfield: sample count is not nx * ny");
  if (!(cell_ > 0.0) || !std::isfinite(cell_)) throw std::invalid_argument("heightfield: cell size must be > 0");
  if (!std::isfinite(x0_) || !std::isfinite(y0_)) throw std::invalid_argument("heightfield: origin must be finite");
  for (float h : coef_)
    if (!std::isfinite(h)) throw std::invalid_argument("heightfield: heights must be finite");
  inv_cell_ = 1.0 / cell_;

  // along x: each row through a double buffer
  std::vector<double> buf(static_cast<std::size_t>(nx_));
  for (int j = 0; j < ny_; ++j) {
    float* row = coef_.data() + static_cast<std::size_t>(j) * nx_;
    for (int i = 0; i < nx_; ++i) buf[i] = 6.0 * row[i];
    prefilter(buf.data(), nx_, 1);
    for (int i = 0; i < nx_; ++i) row[i] = static_cast<float>(buf[i]);
  }
  // along y: blocks of columns, so each row is read in 64-float runs
  constexpr int kBlock = 64;
  buf.assign(static_cast<std::size_t>(kBlock) * ny_, 0.0);
  for (int i0 = 0; i0 < nx_; i0 += kBlock) {
    const int w = std::min(kBlock, nx_ - i0);
    for (int j = 0; j < ny_; ++j)
      for (int b = 0; b < w; ++b) buf[j * kBlock + b] = 6.0 * coef_[static_cast<std::size_t>(j) * nx_ + i0 + b];
    for (int b = 0; b < w; ++b) prefilter(buf.data() + b, ny_, kBlock);
    for (int j = 0; j < ny_; ++j)
      for (int b = 0; b < w; ++b) coef_[static_cast<std::size_t>(j) * nx_ + i0 + b] = static_cast<float>(buf[j * kBlock + b]);
  }
  buf = {};

  // slope bound: the derivative of the spline along x is a quadratic-by-
  // cubic spline whose coefficients are the differences of c along x over
  // the cell (likewise y), with nonnegative weights summing to one
  double gx = 0.0, gy = 0.0;
  for (int j = 0; j < ny_; ++j) {
    const float* row = coef_.data() + static_cast<std::size_t>(j) * nx_;
    for (int i = 0; i + 1 < nx_; ++i) gx = std::max(gx, std::abs(double(row[i + 1]) - double(row[i])));
    if (j + 1 < ny_)
      for (int i = 0; i < nx_; ++i) gy = std::max(gy, std::abs(double(row[i + nx_]) - double(row[i])));
  }
  gx *= inv_cell_;
  gy *= inv_cell_;
  // the margin covers the rounding of the evaluation's sums
  gradient_bound_ = std::sqrt(1.0 + gx * gx + gy * gy) * (1.0 + 1e-9);
}

double HeightfieldGround::maxSlope() const {
  return std::sqrt(std::max(0.0, gradient_bound_ * gradient_bound_ / ((1.0 + 1e-9) * (1.0 + 1e-9)) - 1.0));
}

template <bool kGrad>
double HeightfieldGround::evaluate(double x, double y, double* dhdx, double* dhdy) const {
  int ix[4], iy[4];
  double tx, ty;
  const bool cx = locate((x - x0_) * inv_cell_, nx_, ix, &tx);
  const bool cy = locate((y - y0_) * inv_cell_, ny_, iy, &ty);
  double wx[4], dx[4], wy[4], dy[4];
  weights(tx, wx, dx);
  weights(ty, wy, dy);
  double h = 0.0, hu = 0.0, hv = 0.0;
  for (int b = 0; b < 4; ++b) {
    const float* row = coef_.data() + static_cast<std::size_t>(iy[b]) * nx_;
    const double c0 = row[ix[0]], c1 = row[ix[1]], c2 = row[ix[2]], c3 = row[ix[3]];
    const double s = wx[0] * c0 + wx[1] * c1 + wx[2] * c2 + wx[3] * c3;
    h += wy[b] * s;
    if constexpr (kGrad) {
      hv += dy[b] * s;
      hu += wy[b] * (dx[0] * c0 + dx[1] * c1 + dx[2] * c2 + dx[3] * c3);
    }
  }
  if constexpr (kGrad) {
    *dhdx = cx ? 0.0 : hu * inv_cell_;
    *dhdy = cy ? 0.0 : hv * inv_cell_;
  }
  return h;
}

double HeightfieldGround::height(double x, double y, double* dhdx, double* dhdy) const {
  if (!dhdx && !dhdy) return evaluate<false>(x, y, nullptr, nullptr);
  double hx, hy;
  const double h = evaluate<true>(x, y, &hx, &hy);
  if (dhdx) *dhdx = hx;
  if (dhdy) *dhdy = hy;
  return h;
}

double HeightfieldGround::eval(const Vec3& p, Vec3* grad) const {
  double hx, hy;
  const double h = evaluate<true>(p.x(), p.y(), &hx, &hy);
  *grad = Vec3(-hx, -hy, 1.0);
  return p.z() - h;
}

void HeightfieldGround::heights(const double* x, const double* y, const double* z, int begin, int end,
                                double* H) const {
  for (int k = begin; k < end; ++k) H[k] = z[k] - evaluate<false>(x[k], y[k], nullptr, nullptr);
}

std::string HeightfieldGround::describe() const {
  std::ostringstream s;
  s << "heightfield " << nx_ << " x " << ny_ << " samples, cell " << cell_ << " m, origin (" << x0_ << ", "
    << y0_ << "), max slope " << maxSlope();
  return s.str();
}

}  // namespace groundsim
