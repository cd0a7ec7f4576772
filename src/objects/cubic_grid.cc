#include "objects/cubic_grid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace semvox {
namespace {

// Keys' cubic convolution kernel, a = -1/2.
double Keys(double t) {
  t = std::abs(t);
  if (t < 1) return (1.5 * t - 2.5) * t * t + 1;
  if (t < 2) return ((-0.5 * t + 2.5) * t - 4) * t + 2;
  return 0;
}

bool Bounds(const float* f, int n, int d, std::vector<double>* lo, std::vector<double>* hi) {
  lo->assign(size_t(d), 0.0);
  hi->assign(size_t(d), 0.0);
  for (int k = 0; k < d; ++k) (*lo)[size_t(k)] = n > 0 ? f[k] : 0.0, (*hi)[size_t(k)] = (*lo)[size_t(k)];
  for (int p = 0; p < n; ++p)
    for (int k = 0; k < d; ++k) {
      const double v = f[size_t(p) * size_t(d) + size_t(k)];
      if (!std::isfinite(v)) return false;
      (*lo)[size_t(k)] = std::min((*lo)[size_t(k)], v), (*hi)[size_t(k)] = std::max((*hi)[size_t(k)], v);
    }
  return true;
}

// Nodes on axis k: from floor(lo / h) - 1 to floor(hi / h) + 2.
bool ValidSpacing(const std::vector<double>& spacing, int d) {
  if (int(spacing.size()) != d) return false;
  for (double h : spacing)
    if (!(h > 0 && h <= 1)) return false;
  return true;
}

int64_t AxisNodes(double lo, double hi, double h) { return int64_t(std::floor(hi / h)) - int64_t(std::floor(lo / h)) + 4; }

}  // namespace

int64_t CubicGrid::CellsFor(const float* features, int n, int d, const std::vector<double>& spacing) {
  if (d < 1 || d > 4 || !ValidSpacing(spacing, d)) return -1;
  std::vector<double> lo, hi;
  if (!Bounds(features, n, d, &lo, &hi)) return -1;
  double cells = 1;
  for (int k = 0; k < d; ++k) cells *= double(AxisNodes(lo[size_t(k)], hi[size_t(k)], spacing[size_t(k)]));
  return cells > 4e18 ? -1 : int64_t(cells);
}

void CubicGrid::Build(const float* features, int n, int d, const std::vector<double>& spacing) {
  if (d < 1 || d > 4 || n < 0 || !ValidSpacing(spacing, d))
    throw std::invalid_argument("CubicGrid::Build: need n >= 0, 1 <= d <= 4 and d spacings in (0, 1]");
  std::vector<double> lo, hi;
  if (!Bounds(features, n, d, &lo, &hi)) throw std::invalid_argument("CubicGrid::Build: features not finite");
  n_ = n;
  d_ = d;
  size_.assign(size_t(d), 0);
  stride_.assign(size_t(d), 0);
  std::vector<int64_t> first(static_cast<size_t>(d));
  cells_ = 1;
  for (int k = d - 1; k >= 0; --k) {
    first[size_t(k)] = int64_t(std::floor(lo[size_t(k)] / spacing[size_t(k)])) - 1;
    size_[size_t(k)] = int(AxisNodes(lo[size_t(k)], hi[size_t(k)], spacing[size_t(k)]));
    stride_[size_t(k)] = cells_;
    cells_ *= size_[size_t(k)];
  }
  base_.assign(size_t(n), 0);
  weight_.assign(size_t(n) * size_t(d) * 4, 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& range) {
    for (int p = range.begin(); p < range.end(); ++p) {
      int64_t base = 0;
      for (int k = 0; k < d; ++k) {
        const double x = features[size_t(p) * size_t(d) + size_t(k)] / spacing[size_t(k)];
        const double c = std::floor(x), t = x - c;
        base += (int64_t(c) - 1 - first[size_t(k)]) * stride_[size_t(k)];  // Nodes c - 1 .. c + 2.
        float* w = &weight_[(size_t(p) * size_t(d) + size_t(k)) * 4];
        for (int j = 0; j < 4; ++j) w[j] = float(Keys(t - (j - 1)));
      }
      base_[size_t(p)] = base;
    }
  });
  taps_.assign(size_t(d), {});
  for (int k = 0; k < d; ++k) {
    const double h = spacing[size_t(k)];
    const int radius = int(std::ceil(kTruncation / h));
    taps_[size_t(k)].resize(size_t(radius) + 1);
    for (int t = 0; t <= radius; ++t) taps_[size_t(k)][size_t(t)] = std::exp(-0.5 * (t * h) * (t * h));
  }
}

void CubicGrid::Filter(const float* in, int m, std::vector<float>* out) const {
  const size_t cells = size_t(cells_), mm = size_t(m);
  // Corners of the first d - 1 axes (the last axis has stride 1: its 4 nodes are contiguous).
  int prefix = 1;
  for (int k = 0; k + 1 < d_; ++k) prefix *= 4;
  std::vector<int64_t> prefix_offset(static_cast<size_t>(prefix));
  for (int c = 0; c < prefix; ++c) {
    int64_t off = 0;
    for (int k = d_ - 2, rest = c; k >= 0; --k, rest /= 4) off += (rest % 4) * stride_[size_t(k)];
    prefix_offset[size_t(c)] = off;
  }
  // The 4^(d-1) weights of point p's prefix corners (same order as prefix_offset: axis d-2 fastest).
  auto prefix_weights = [&](int p, double* w) {
    w[0] = 1;
    int count = 1;
    for (int k = 0; k + 1 < d_; ++k) {
      const float* wk = &weight_[(size_t(p) * size_t(d_) + size_t(k)) * 4];
      for (int c = count - 1; c >= 0; --c)
        for (int j = 3; j >= 0; --j) w[4 * c + j] = w[c] * wk[j];
      count *= 4;
    }
  };
  // Splat into a fixed number of partial grids (contiguous ranges of points; node-major, m channels per
  // node), summed in a fixed order: deterministic whatever the thread count.
  constexpr int kChunks = 4;
  std::vector<std::vector<double>> partial(kChunks);
  tbb::parallel_for(0, kChunks, [&](int chunk) {
    std::vector<double>& g = partial[size_t(chunk)];
    g.assign(cells * mm, 0.0);
    std::vector<double> w(static_cast<size_t>(prefix)), v(mm);
    const int begin = int(int64_t(n_) * chunk / kChunks), end = int(int64_t(n_) * (chunk + 1) / kChunks);
    for (int p = begin; p < end; ++p) {
      prefix_weights(p, w.data());
      const float* wl = &weight_[(size_t(p) * size_t(d_) + size_t(d_ - 1)) * 4];
      const float* src = in + size_t(p) * mm;
      for (int c = 0; c < prefix; ++c) {
        double* dst = &g[size_t(base_[size_t(p)] + prefix_offset[size_t(c)]) * mm];
        for (int j = 0; j < 4; ++j) {
          const double wj = w[size_t(c)] * wl[j];
          for (size_t ch = 0; ch < mm; ++ch) dst[size_t(j) * mm + ch] += wj * src[ch];
        }
      }
    }
  });
  std::vector<double> grid(std::move(partial[0])), next(cells * mm, 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cells * mm, 1 << 14), [&](const tbb::blocked_range<size_t>& range) {
    for (int chunk = 1; chunk < kChunks; ++chunk)
      for (size_t i = range.begin(); i < range.end(); ++i) grid[i] += partial[size_t(chunk)][i];
  });
  partial.clear();
  // Separable blur along each axis: lines of the grid (all channels) in parallel.
  for (int k = 0; k < d_; ++k) {
    const std::vector<double>& taps = taps_[size_t(k)];
    const int radius = int(taps.size()) - 1;
    const int len = size_[size_t(k)];
    const int64_t stride = stride_[size_t(k)];
    const int64_t lines = int64_t(cells) / len;
    tbb::parallel_for(tbb::blocked_range<int64_t>(0, lines, 16), [&](const tbb::blocked_range<int64_t>& range) {
      std::vector<double> line(size_t(len) * mm), acc(mm);
      for (int64_t l = range.begin(); l < range.end(); ++l) {
        // Line l: all axes but k; its first node has index (l / stride) * stride * len + l % stride.
        const int64_t start = (l / stride) * stride * len + l % stride;
        for (int i = 0; i < len; ++i)
          std::copy_n(&grid[size_t(start + int64_t(i) * stride) * mm], mm, &line[size_t(i) * mm]);
        for (int i = 0; i < len; ++i) {
          std::fill(acc.begin(), acc.end(), 0.0);
          const int a = std::max(0, i - radius), z = std::min(len - 1, i + radius);
          for (int j = a; j <= z; ++j) {
            const double t = taps[size_t(std::abs(j - i))];
            const double* src = &line[size_t(j) * mm];
            for (size_t ch = 0; ch < mm; ++ch) acc[ch] += t * src[ch];
          }
          std::copy_n(acc.data(), mm, &next[size_t(start + int64_t(i) * stride) * mm]);
        }
      }
    });
    grid.swap(next);
  }
  // Slice.
  out->assign(size_t(n_) * mm, 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, n_, 1024), [&](const tbb::blocked_range<int>& range) {
    std::vector<double> acc(mm), w(static_cast<size_t>(prefix));
    for (int p = range.begin(); p < range.end(); ++p) {
      prefix_weights(p, w.data());
      const float* wl = &weight_[(size_t(p) * size_t(d_) + size_t(d_ - 1)) * 4];
      std::fill(acc.begin(), acc.end(), 0.0);
      for (int c = 0; c < prefix; ++c) {
        const double* src = &grid[size_t(base_[size_t(p)] + prefix_offset[size_t(c)]) * mm];
        for (int j = 0; j < 4; ++j) {
          const double wj = w[size_t(c)] * wl[j];
          for (size_t ch = 0; ch < mm; ++ch) acc[ch] += wj * src[size_t(j) * mm + ch];
        }
      }
      for (size_t ch = 0; ch < mm; ++ch) (*out)[size_t(p) * mm + ch] = float(acc[ch]);
    }
  });
}

}  // namespace semvox
