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

namespace {

// Splat and slice of one point, M channels (M = 0: m at run time). `corner_offset` / `corner_weight`: the
// 4^(d-1) prefix corners' node offsets and weights; `last`: the 4 weights of the last axis, whose nodes are
// contiguous (stride 1), so that one corner touches 4 * m consecutive floats of the node-major grid.
template <int M>
void SplatPoint(const int64_t* corner_offset, const float* corner_weight, int corners, const float* last, const float* value,
                int m_runtime, int64_t base, float* grid) {
  const int m = M > 0 ? M : m_runtime;
  float u[4 * 8];  // 4 nodes x m channels (m <= 8 on this path).
  for (int j = 0; j < 4; ++j)
    for (int ch = 0; ch < m; ++ch) u[j * m + ch] = last[j] * value[ch];
  for (int c = 0; c < corners; ++c) {
    float* dst = grid + size_t(base + corner_offset[c]) * size_t(m);
    const float w = corner_weight[c];
    for (int i = 0; i < 4 * m; ++i) dst[i] += w * u[i];
  }
}

template <int M>
void SlicePoint(const int64_t* corner_offset, const float* corner_weight, int corners, const float* last, const float* grid,
                int m_runtime, int64_t base, float* out) {
  const int m = M > 0 ? M : m_runtime;
  float acc[4 * 8] = {};
  for (int c = 0; c < corners; ++c) {
    const float* src = grid + size_t(base + corner_offset[c]) * size_t(m);
    const float w = corner_weight[c];
    for (int i = 0; i < 4 * m; ++i) acc[i] += w * src[i];
  }
  for (int ch = 0; ch < m; ++ch) out[ch] = last[0] * acc[ch] + last[1] * acc[m + ch] + last[2] * acc[2 * m + ch] + last[3] * acc[3 * m + ch];
}

// The blur along the last axis (stride 1) of lines [begin, end) of `len` nodes, m channels (M = 0: m at run
// time), accumulated in double tap by tap from the lowest node up.
template <int M>
void BlurLastAxis(const float* grid, float* next, int64_t begin, int64_t end, int len, const std::vector<double>& taps,
                  int m_runtime) {
  const size_t mm = size_t(M > 0 ? M : m_runtime);
  const int radius = int(taps.size()) - 1;
  double acc[8];  // m <= 8 on this path.
  for (int64_t l = begin; l < end; ++l) {
    const float* line = &grid[size_t(l) * size_t(len) * mm];
    float* out_line = &next[size_t(l) * size_t(len) * mm];
    for (int i = 0; i < len; ++i) {
      for (size_t ch = 0; ch < mm; ++ch) acc[ch] = 0.0;
      const int a = std::max(0, i - radius), z = std::min(len - 1, i + radius);
      for (int j = a; j <= z; ++j) {
        const double t = taps[size_t(std::abs(j - i))];
        const float* src = &line[size_t(j) * mm];
        for (size_t ch = 0; ch < mm; ++ch) acc[ch] += t * src[ch];
      }
      for (size_t ch = 0; ch < mm; ++ch) out_line[size_t(i) * mm + ch] = float(acc[ch]);
    }
  }
}

}  // namespace

void CubicGrid::Filter(const float* in, int m, std::vector<float>* out) const {
  if (m > 8) {
    // Wide inputs: filter in groups of at most 8 channels (the per-point buffers above hold 4 x 8 values).
    out->assign(size_t(n_) * size_t(m), 0.f);
    std::vector<float> part_in, part_out;
    for (int first = 0; first < m; first += 8) {
      const int k = std::min(8, m - first);
      part_in.resize(size_t(n_) * size_t(k));
      for (int p = 0; p < n_; ++p)
        std::copy_n(in + size_t(p) * size_t(m) + size_t(first), k, &part_in[size_t(p) * size_t(k)]);
      Filter(part_in.data(), k, &part_out);
      for (int p = 0; p < n_; ++p)
        std::copy_n(&part_out[size_t(p) * size_t(k)], k, out->data() + size_t(p) * size_t(m) + size_t(first));
    }
    return;
  }
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
  auto prefix_weights = [&](int p, float* w) {
    w[0] = 1;
    int count = 1;
    for (int k = 0; k + 1 < d_; ++k) {
      const float* wk = &weight_[(size_t(p) * size_t(d_) + size_t(k)) * 4];
      for (int c = count - 1; c >= 0; --c)
        for (int j = 3; j >= 0; --j) w[4 * c + j] = w[c] * wk[j];
      count *= 4;
    }
  };
  auto splat = [&](int p, const float* w, float* g) {
    const float* wl = &weight_[(size_t(p) * size_t(d_) + size_t(d_ - 1)) * 4];
    const float* src = in + size_t(p) * mm;
    switch (m) {
      case 1: SplatPoint<1>(prefix_offset.data(), w, prefix, wl, src, m, base_[size_t(p)], g); break;
      case 2: SplatPoint<2>(prefix_offset.data(), w, prefix, wl, src, m, base_[size_t(p)], g); break;
      case 3: SplatPoint<3>(prefix_offset.data(), w, prefix, wl, src, m, base_[size_t(p)], g); break;
      case 4: SplatPoint<4>(prefix_offset.data(), w, prefix, wl, src, m, base_[size_t(p)], g); break;
      default: SplatPoint<0>(prefix_offset.data(), w, prefix, wl, src, m, base_[size_t(p)], g); break;
    }
  };
  // Splat into a fixed number of partial grids (contiguous ranges of points; node-major, m channels per
  // node, float), summed in a fixed order: deterministic whatever the thread count.
  constexpr int kChunks = 4;
  std::vector<std::vector<float>> partial(kChunks);
  tbb::parallel_for(0, kChunks, [&](int chunk) {
    std::vector<float>& g = partial[size_t(chunk)];
    g.assign(cells * mm, 0.f);
    std::vector<float> w(static_cast<size_t>(prefix));
    const int begin = int(int64_t(n_) * chunk / kChunks), end = int(int64_t(n_) * (chunk + 1) / kChunks);
    for (int p = begin; p < end; ++p) {
      prefix_weights(p, w.data());
      splat(p, w.data(), g.data());
    }
  });
  std::vector<float> grid(std::move(partial[0])), next(cells * mm, 0.f);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cells * mm, 1 << 14), [&](const tbb::blocked_range<size_t>& range) {
    for (int chunk = 1; chunk < kChunks; ++chunk)
      for (size_t i = range.begin(); i < range.end(); ++i) grid[i] += partial[size_t(chunk)][i];
  });
  partial.clear();
  // Separable blur along each axis. Axes before the last: the nodes at one position of the axis form a
  // contiguous run of stride * m values (all later axes and channels), so an output run is a weighted sum of
  // whole input runs (vectorisable). The last axis (stride 1): lines of len nodes, double accumulation.
  for (int k = 0; k < d_; ++k) {
    const std::vector<double>& taps = taps_[size_t(k)];
    const int radius = int(taps.size()) - 1;
    const int len = size_[size_t(k)];
    const int64_t stride = stride_[size_t(k)];
    if (stride > 1) {
      const size_t run = size_t(stride) * mm;
      const int64_t blocks = int64_t(cells) / (int64_t(len) * stride);
      std::vector<float> tapf(taps.begin(), taps.end());
      tbb::parallel_for(tbb::blocked_range<int64_t>(0, blocks * len, 1), [&](const tbb::blocked_range<int64_t>& range) {
        for (int64_t r = range.begin(); r < range.end(); ++r) {
          const int64_t block = r / len;
          const int i = int(r % len);
          const size_t first = size_t(block) * size_t(len) * run;
          float* dst = &next[first + size_t(i) * run];
          std::fill(dst, dst + run, 0.f);
          const int a = std::max(0, i - radius), z = std::min(len - 1, i + radius);
          for (int j = a; j <= z; ++j) {
            const float t = tapf[size_t(std::abs(j - i))];
            const float* src = &grid[first + size_t(j) * run];
            for (size_t v = 0; v < run; ++v) dst[v] += t * src[v];
          }
        }
      });
    } else {
      const int64_t lines = int64_t(cells) / len;
      tbb::parallel_for(tbb::blocked_range<int64_t>(0, lines, 16), [&](const tbb::blocked_range<int64_t>& range) {
        switch (m) {
          case 1: BlurLastAxis<1>(grid.data(), next.data(), range.begin(), range.end(), len, taps, m); break;
          case 2: BlurLastAxis<2>(grid.data(), next.data(), range.begin(), range.end(), len, taps, m); break;
          case 3: BlurLastAxis<3>(grid.data(), next.data(), range.begin(), range.end(), len, taps, m); break;
          case 4: BlurLastAxis<4>(grid.data(), next.data(), range.begin(), range.end(), len, taps, m); break;
          default: BlurLastAxis<0>(grid.data(), next.data(), range.begin(), range.end(), len, taps, m); break;
        }
      });
    }
    grid.swap(next);
  }
  // Slice.
  out->assign(size_t(n_) * mm, 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, n_, 1024), [&](const tbb::blocked_range<int>& range) {
    std::vector<float> w(static_cast<size_t>(prefix));
    for (int p = range.begin(); p < range.end(); ++p) {
      prefix_weights(p, w.data());
      const float* wl = &weight_[(size_t(p) * size_t(d_) + size_t(d_ - 1)) * 4];
      float* dst = out->data() + size_t(p) * mm;
      switch (m) {
        case 1: SlicePoint<1>(prefix_offset.data(), w.data(), prefix, wl, grid.data(), m, base_[size_t(p)], dst); break;
        case 2: SlicePoint<2>(prefix_offset.data(), w.data(), prefix, wl, grid.data(), m, base_[size_t(p)], dst); break;
        case 3: SlicePoint<3>(prefix_offset.data(), w.data(), prefix, wl, grid.data(), m, base_[size_t(p)], dst); break;
        case 4: SlicePoint<4>(prefix_offset.data(), w.data(), prefix, wl, grid.data(), m, base_[size_t(p)], dst); break;
        default: SlicePoint<0>(prefix_offset.data(), w.data(), prefix, wl, grid.data(), m, base_[size_t(p)], dst); break;
      }
    }
  });
}

}  // namespace semvox
