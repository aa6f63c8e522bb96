// SSIM's window sums (see ssim.h).
#include "metrics/ssim.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "metrics/detail.h"

namespace aovar::metrics::detail {

namespace {

constexpr int kRadius = 5;  // 11 taps
constexpr int kTaps = 2 * kRadius + 1;
constexpr double kSigma = 1.5;
constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;

// Normalised 1-D Gaussian taps, index 0 = offset -kRadius.
const std::array<double, kTaps>& gaussian_taps() {
  static const std::array<double, kTaps> taps = [] {
    std::array<double, kTaps> t{};
    double sum = 0;
    for (int k = -kRadius; k <= kRadius; ++k) sum += t[k + kRadius] = std::exp(-(k * k) / (2 * kSigma * kSigma));
    for (double& v : t) v /= sum;
    return t;
  }();
  return taps;
}

// Two pixels at once in one vector (GCC's and Clang's vector extension; SSE2 on x86-64, NEON on arm64): an
// element-wise IEEE operation rounds as the scalar one does, so the lanes give the scalar loop's bits.
constexpr int kLanes = 2;
using Lanes = double __attribute__((vector_size(kLanes * sizeof(double))));

Lanes load(const double* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

void store(double* p, const Lanes& v) { std::memcpy(p, &v, sizeof v); }

// Three channels' horizontal window sums at once: over each row's taps j, lin = the sum of g * p[j], sq = of
// (g * p[j]) * p[j], cross = of (g * p[j]) * q[j]. Interior pixels take every tap, four pixels at a time; the
// pixels within kRadius of a row's ends take the taps inside the row, one pixel at a time.
void horizontal(const double* p, const double* q, int w, int h, double* lin, double* sq, double* cross) {
  const auto& taps = gaussian_taps();
  auto one = [&](std::size_t row, int x) {
    double l = 0, s = 0, c = 0;
    for (int k = std::max(0, kRadius - x); k < kTaps && x + k - kRadius < w; ++k) {
      const std::size_t j = row + x + k - kRadius;
      const double gp = taps[k] * p[j];
      l += gp, s += gp * p[j], c += gp * q[j];
    }
    lin[row + x] = l, sq[row + x] = s, cross[row + x] = c;
  };
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * w;
    int x = 0;
    for (; x < std::min(kRadius, w); ++x) one(row, x);
    for (; x + kLanes <= w - kRadius; x += kLanes) {
      Lanes l{}, s{}, c{};
      for (int k = 0; k < kTaps; ++k) {
        const std::size_t j = row + x + k - kRadius;
        const Lanes pv = load(p + j), gp = taps[k] * pv;
        l += gp, s += gp * pv, c += gp * load(q + j);
      }
      store(lin + row + x, l), store(sq + row + x, s), store(cross + row + x, c);
    }
    for (; x < w; ++x) one(row, x);
  }
}

// Row y of a channel's vertical window sums of its horizontal sums `in`.
void vertical_row(const double* in, int w, int h, int y, double* out) {
  const auto& taps = gaussian_taps();
  const int lo = std::max(y - kRadius, 0), hi = std::min(y + kRadius, h - 1);
  int x = 0;
  for (; x + kLanes <= w; x += kLanes) {
    Lanes sum{};
    for (int yy = lo; yy <= hi; ++yy) sum += taps[yy - y + kRadius] * load(in + static_cast<std::size_t>(yy) * w + x);
    store(out + x, sum);
  }
  for (; x < w; ++x) {
    double sum = 0;
    for (int yy = lo; yy <= hi; ++yy) sum += taps[yy - y + kRadius] * in[static_cast<std::size_t>(yy) * w + x];
    out[x] = sum;
  }
}

void vertical(const double* in, int w, int h, double* out) {
  for (int y = 0; y < h; ++y) vertical_row(in, w, h, y, out + static_cast<std::size_t>(y) * w);
}

// Scratch reused across calls on one thread: a comparison's buffers are megabytes, and fresh ones would be
// paged in (and zeroed by the kernel) on every call.
std::vector<double>& scratch(int which, std::size_t n) {
  thread_local std::array<std::vector<double>, 6> buffers;
  buffers[which].resize(n);
  return buffers[which];
}

}  // namespace

ReferenceMoments reference_moments(const image::FloatImage& reference, std::vector<std::uint8_t> valid) {
  const int w = reference.width, h = reference.height;
  const std::size_t n = pixel_count(reference);
  ReferenceMoments m;
  m.valid = std::move(valid);
  m.masked.assign(n, 0.0);
  std::vector<double> weight(n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (m.valid[i]) m.masked[i] = reference.pixels[i], weight[i] = 1.0;
  std::vector<double> hw(n), hy(n), hyy(n), unused(n);
  horizontal(weight.data(), weight.data(), w, h, hw.data(), unused.data(), unused.data());  // g * 1 = g
  horizontal(m.masked.data(), m.masked.data(), w, h, hy.data(), hyy.data(), unused.data());
  m.w.resize(n), m.y.resize(n), m.yy.resize(n);
  vertical(hw.data(), w, h, m.w.data());
  vertical(hy.data(), w, h, m.y.data());
  vertical(hyy.data(), w, h, m.yy.data());
  return m;
}

double ssim_sum(const image::FloatImage& image, const ReferenceMoments& ref) {
  const int w = image.width, h = image.height;
  const std::size_t n = pixel_count(image);
  std::vector<double>& a = scratch(0, n);
  for (std::size_t i = 0; i < n; ++i) a[i] = ref.valid[i] ? static_cast<double>(image.pixels[i]) : 0.0;
  std::vector<double>&hx = scratch(1, n), &hxx = scratch(2, n), &hxy = scratch(3, n);
  horizontal(a.data(), ref.masked.data(), w, h, hx.data(), hxx.data(), hxy.data());

  std::vector<double>& cols = scratch(4, 3 * static_cast<std::size_t>(w));
  double *vx_sum = cols.data(), *vxx_sum = vx_sum + w, *vxy_sum = vxx_sum + w;
  double sum = 0;
  for (int y = 0; y < h; ++y) {
    vertical_row(hx.data(), w, h, y, vx_sum);
    vertical_row(hxx.data(), w, h, y, vxx_sum);
    vertical_row(hxy.data(), w, h, y, vxy_sum);
    const std::size_t row = static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      const std::size_t i = row + x;
      if (!ref.valid[i]) continue;
      // ref.w[i] > 0: the centre pixel itself is valid.
      const double mw = ref.w[i];
      const double mx = vx_sum[x] / mw, my = ref.y[i] / mw;
      const double vx = std::max(vxx_sum[x] / mw - mx * mx, 0.0);
      const double vy = std::max(ref.yy[i] / mw - my * my, 0.0);
      const double cxy = vxy_sum[x] / mw - mx * my;
      sum += ((2 * mx * my + kC1) * (2 * cxy + kC2)) / ((mx * mx + my * my + kC1) * (vx + vy + kC2));
    }
  }
  return sum;
}

}  // namespace aovar::metrics::detail
