#include "objects/dense_crf.h"

#include <tbb/parallel_for.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace semvox {
namespace {

// One pixel's unary: its probabilities clamped below by `floor` and renormalised into q, psi_u = -log q.
void NegLogUnary(const float* probabilities, int m, float floor, float* unary, float* q) {
  float s = 0;
  for (int l = 0; l < m; ++l) s += std::max(floor, probabilities[l]);
  for (int l = 0; l < m; ++l) {
    const float p = std::max(floor, probabilities[l]) / s;
    unary[l] = -std::log(p);
    q[l] = p;
  }
}

// One pixel's mean-field update (K&K 2011 Algorithm 1): q(l) ~ exp(-psi_u(l) + message(l)).
void UpdatePixel(const float* unary, const float* message, int m, float* q) {
  float best = -1e30f;
  for (int l = 0; l < m; ++l) {
    q[l] = -unary[l] + message[l];
    best = std::max(best, q[l]);
  }
  float s = 0;
  for (int l = 0; l < m; ++l) s += (q[l] = std::exp(q[l] - best));
  for (int l = 0; l < m; ++l) q[l] /= s;
}

}  // namespace

bool DenseCrfOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  auto num = [](double v) { return std::to_string(v); };
  if (!CheckOptions(*this, Options(), error)) return false;
  const std::pair<const char*, double> weights[] = {{"appearance_weight", appearance_weight}, {"smoothness_weight", smoothness_weight},
                                                    {"height_weight", height_weight}, {"normal_weight", normal_weight}};
  for (const auto& [name, v] : weights)
    if (!(v >= 0)) return fail(std::string(name) + " = " + num(v) + ". Violated constraint: " + name + " >= 0");
  const std::pair<const char*, double> scales[] = {{"position_scale_px", position_scale_px}, {"colour_scale", colour_scale},
                                                   {"smoothness_scale_px", smoothness_scale_px}, {"height_scale_m", height_scale_m},
                                                   {"normal_scale", normal_scale}};
  for (const auto& [name, v] : scales)
    if (!(v > 0)) return fail(std::string(name) + " = " + num(v) + ". Violated constraint: " + name + " > 0");
  if (!(height_grid_spacing >= 0 && height_grid_spacing <= 1))
    return fail("height_grid_spacing = " + num(height_grid_spacing) + ". Violated constraint: 0 <= height_grid_spacing <= 1");
  if (!(height_grid_position_spacing > 0 && height_grid_position_spacing <= 1))
    return fail("height_grid_position_spacing = " + num(height_grid_position_spacing) + ". Violated constraint: 0 < height_grid_position_spacing <= 1");
  if (!(probability_floor > 0 && probability_floor < 0.5))
    return fail("probability_floor = " + num(probability_floor) + ". Violated constraint: 0 < probability_floor < 0.5");
  const std::pair<const char*, int> refinements[] = {{"lattice_refinement", lattice_refinement}, {"lattice_refinement_5d", lattice_refinement_5d}};
  for (const auto& [name, v] : refinements)
    if (v < 1 || v > PermutohedralLattice::kMaxRefinement)
      return fail(std::string(name) + " = " + std::to_string(v) + ". Violated constraint: 1 <= " + name +
                  " <= " + std::to_string(PermutohedralLattice::kMaxRefinement));
  return true;
}

Result<DenseCrf> DenseCrf::Create(const DenseCrfInput& input, const DenseCrfOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("dense CRF options: " + error);
  if (!input.rgb || input.rgb->channels != 3 || input.rgb->empty()) return Status::InvalidInput("dense CRF: need a 3-channel RGB image");
  const int w = input.rgb->width, h = input.rgb->height;
  if (!input.height || input.height->width != w || input.height->height != h || input.height->channels != 1)
    return Status::InvalidInput("dense CRF: the height image must be 1 channel of the RGB image's size");
  if (!input.normal || input.normal->width != w || input.normal->height != h || input.normal->channels != 3)
    return Status::InvalidInput("dense CRF: the normal image must be 3 channels of the RGB image's size");
  DenseCrf crf;
  crf.n_ = w * h;
  crf.width_ = w, crf.height_ = h;
  crf.options_ = options;
  const size_t n = size_t(crf.n_);
  auto add = [&](double weight, int dims, auto&& fill) {
    if (weight <= 0) return;
    Kernel k;
    k.weight = weight;
    k.dims = dims;
    k.features.resize(n * size_t(dims));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) fill(x, y, &k.features[(size_t(y) * size_t(w) + size_t(x)) * size_t(dims)]);
    crf.kernels_.push_back(std::move(k));
  };
  const float sb = float(1.0 / options.position_scale_px), sv = float(1.0 / options.colour_scale);
  const float sp = float(1.0 / options.smoothness_scale_px), sq = float(1.0 / options.height_scale_m);
  const float sn = float(1.0 / options.normal_scale);
  add(options.appearance_weight, 5, [&](int x, int y, float* f) {
    f[0] = x * sb, f[1] = y * sb;
    for (int c = 0; c < 3; ++c) f[2 + c] = input.rgb->at(x, y, c) * sv;
  });
  add(options.smoothness_weight, 2, [&](int x, int y, float* f) { f[0] = x * sp, f[1] = y * sp; });
  add(options.height_weight, 3, [&](int x, int y, float* f) {
    f[0] = x * sb, f[1] = y * sb, f[2] = input.height->at(x, y) * sq;
  });
  add(options.normal_weight, 5, [&](int x, int y, float* f) {
    f[0] = x * sb, f[1] = y * sb;
    for (int c = 0; c < 3; ++c) f[2 + c] = input.normal->at(x, y, c) * sn;
  });
  for (Kernel& k : crf.kernels_) {
    if (k.dims == 2 && options.exact_smoothness) {
      // The smoothness kernel's features are (x, y) / theta_p for every pixel of the w x h grid: separable.
      const int radius = int(std::ceil(5.0 * options.smoothness_scale_px));
      k.grid_taps.resize(size_t(radius) + 1);
      for (int t = 0; t <= radius; ++t) k.grid_taps[size_t(t)] = float(std::exp(-0.5 * (t * sp) * (t * sp)));
      continue;
    }
    if (k.dims == 3 && options.height_grid_spacing > 0) {
      const std::vector<double> spacing = {options.height_grid_position_spacing, options.height_grid_position_spacing, options.height_grid_spacing};
      const int64_t cells = CubicGrid::CellsFor(k.features.data(), crf.n_, 3, spacing);
      if (cells >= 0 && cells <= DenseCrfOptions::kMaxGridCells) {
        k.cubic.Build(k.features.data(), crf.n_, 3, spacing);
        k.on_cubic_grid = true;
        continue;
      }
    }
    const int refinement = k.dims > 3 ? options.lattice_refinement_5d : options.lattice_refinement;
    k.lattice.Build(k.features.data(), crf.n_, k.dims, refinement);
  }
  // The normaliser of every kernel does not change between iterations: filter a channel of ones once.
  const std::vector<float> ones(n, 1.f);
  for (Kernel& k : crf.kernels_) crf.Filter(k, ones, 1, &k.normaliser);
  return crf;
}

void DenseCrf::BruteForceMessage(int i, const std::vector<float>& q, int m, float* out) const {
  std::fill(out, out + m, 0.f);
  std::vector<double> acc(static_cast<size_t>(m));
  for (const Kernel& k : kernels_) {
    const float* fi = &k.features[size_t(i) * size_t(k.dims)];
    std::fill(acc.begin(), acc.end(), 0.0);
    double z = 0;
    for (int j = 0; j < n_; ++j) {
      const float* fj = &k.features[size_t(j) * size_t(k.dims)];
      float d2 = 0;
      for (int c = 0; c < k.dims; ++c) d2 += (fi[c] - fj[c]) * (fi[c] - fj[c]);
      if (d2 > 60.f) continue;  // exp(-30) < 1e-13: below float resolution of these sums.
      const double g = std::exp(-0.5 * double(d2));
      z += g;
      for (int l = 0; l < m; ++l) acc[size_t(l)] += g * q[size_t(j) * size_t(m) + size_t(l)];
    }
    for (int l = 0; l < m; ++l) out[l] += float(k.weight * acc[size_t(l)] / z);
  }
}

void DenseCrf::Filter(const Kernel& k, const std::vector<float>& in, int m1, std::vector<float>* out) const {
  if (k.on_cubic_grid) {
    k.cubic.Filter(in.data(), m1, out);
    return;
  }
  if (k.grid_taps.empty()) {
    k.lattice.Filter(in.data(), m1, out);
    return;
  }
  // Exact Gaussian on the pixel grid, truncated at |dx|, |dy| > R: rows, then columns, each pass parallel
  // over rows and vectorised along the row (tap by tap). out_i = sum_j g(x_i - x_j) g(y_i - y_j) in_j over
  // the image (pixels outside it are absent, as in the exact sum).
  const int w = width_, h = height_, radius = int(k.grid_taps.size()) - 1;
  const size_t m = size_t(m1), row = size_t(w) * m;
  const float* g = k.grid_taps.data();
  std::vector<float> tmp(in.size());
  out->assign(in.size(), 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      const float* src = &in[size_t(y) * row];
      float* dst = &tmp[size_t(y) * row];
      for (size_t c = 0; c < row; ++c) dst[c] = g[0] * src[c];
      for (int t = 1; t <= radius && t < w; ++t) {
        const size_t shift = size_t(t) * m;
        const float gt = g[t];
        for (size_t c = 0; c + shift < row; ++c) dst[c] += gt * src[c + shift];  // x_j = x + t
        for (size_t c = shift; c < row; ++c) dst[c] += gt * src[c - shift];      // x_j = x - t
      }
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& range) {
    for (int y = range.begin(); y < range.end(); ++y) {
      float* dst = &(*out)[size_t(y) * row];
      const int lo = std::max(0, y - radius), hi = std::min(h - 1, y + radius);
      for (int yj = lo; yj <= hi; ++yj) {
        const float gw = g[std::abs(yj - y)];
        const float* s = &tmp[size_t(yj) * row];
        for (size_t c = 0; c < row; ++c) dst[c] += gw * s[c];
      }
    }
  });
}

void DenseCrf::Messages(const std::vector<float>& q, int m, bool brute_force, std::vector<float>* out) const {
  Messages(q, m, brute_force, false, out);
}

void DenseCrf::Messages(const std::vector<float>& q, int m, bool brute_force, bool rows_sum_to_one, std::vector<float>* out) const {
  out->assign(size_t(n_) * size_t(m), 0.f);
  if (brute_force) {
    tbb::parallel_for(tbb::blocked_range<int>(0, n_, 16), [&](const tbb::blocked_range<int>& range) {
      for (int i = range.begin(); i < range.end(); ++i) BruteForceMessage(i, q, m, &(*out)[size_t(i) * size_t(m)]);
    });
    return;
  }
  // The normalisers Z_i = sum_j k(f_i, f_j) were filtered once in Create. When every row of q sums to 1 (the
  // mean-field marginals), the last label's sum is Z_i minus the others' (every filter is linear): only m - 1
  // channels are filtered.
  const size_t n = size_t(n_), mm = size_t(m), m1 = rows_sum_to_one && mm > 1 ? mm - 1 : mm;
  std::vector<float> head;
  if (m1 < mm) {
    head.resize(n * m1);
    for (size_t i = 0; i < n; ++i) std::copy_n(&q[i * mm], m1, &head[i * m1]);
  }
  std::vector<float> filtered;
  for (const Kernel& k : kernels_) {
    Filter(k, m1 < mm ? head : q, int(m1), &filtered);
    const float w = float(k.weight);
    for (size_t i = 0; i < n; ++i) {
      const float z = k.normaliser[i];
      if (!(z > 0)) continue;
      float rest = z;
      for (size_t l = 0; l < m1; ++l) {
        const float f = filtered[i * m1 + l];
        rest -= f;
        (*out)[i * mm + l] += w * std::max(0.f, f) / z;
      }
      if (m1 < mm) (*out)[i * mm + m1] += w * std::max(0.f, rest) / z;
    }
  }
}

std::vector<float> DenseCrf::MeanField(const std::vector<float>& probabilities, int m, bool brute_force) const {
  const size_t n = size_t(n_);
  std::vector<float> unary(n * size_t(m)), q(n * size_t(m));
  const float floor = float(options_.probability_floor);
  // Initialise Q with the normalised unary (K&K Algorithm 1), psi_u = -log p.
  for (size_t i = 0; i < n; ++i) NegLogUnary(&probabilities[i * size_t(m)], m, floor, &unary[i * size_t(m)], &q[i * size_t(m)]);
  std::vector<float> messages;
  for (int it = 0; it < options_.iterations; ++it) {
    Messages(q, m, brute_force, true, &messages);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i < range.end(); ++i)
        UpdatePixel(&unary[i * size_t(m)], &messages[i * size_t(m)], m, &q[i * size_t(m)]);
    });
  }
  return q;
}

Result<std::vector<float>> CoarseGridMeanField(const DenseCrfInput& input, const DenseCrfOptions& options,
                                               const std::vector<float>& probabilities, int m, int factor) {
  if (factor < 1) return Status::InvalidInput("dense CRF: grid factor " + std::to_string(factor) + " < 1");
  if (!input.rgb || !input.height || !input.normal) return Status::InvalidInput("dense CRF: need the RGB, height and normal images");
  const int w = input.rgb->width, h = input.rgb->height;
  const size_t n = size_t(w) * size_t(h), mm = size_t(m);
  if (m < 1 || probabilities.size() != n * mm)
    return Status::InvalidInput("dense CRF: " + std::to_string(probabilities.size()) + " unary probabilities for " + std::to_string(n) +
                                " pixels and " + std::to_string(m) + " labels");
  if (factor == 1 || options.iterations == 0) {
    Result<DenseCrf> crf = DenseCrf::Create(input, options);
    if (!crf.ok()) return crf.status();
    return crf->MeanField(probabilities, m);
  }
  const int cw = (w + factor - 1) / factor, ch = (h + factor - 1) / factor;
  ImageRgb8 rgb(cw, ch, 3, 0);
  ImageF32 height(cw, ch, 1, 0.f), normal(cw, ch, 3, 0.f);
  std::vector<float> p(size_t(cw) * size_t(ch) * mm, 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, ch, 4), [&](const tbb::blocked_range<int>& range) {
    for (int by = range.begin(); by < range.end(); ++by)
      for (int bx = 0; bx < cw; ++bx) {
        float colour[3] = {0, 0, 0}, z = 0;
        Eigen::Vector3f nsum = Eigen::Vector3f::Zero();
        int count = 0, with_depth = 0;
        float* pb = &p[(size_t(by) * size_t(cw) + size_t(bx)) * mm];
        for (int y = by * factor; y < std::min(h, (by + 1) * factor); ++y)
          for (int x = bx * factor; x < std::min(w, (bx + 1) * factor); ++x) {
            ++count;
            for (int c = 0; c < 3; ++c) colour[c] += float(input.rgb->at(x, y, c));
            const Eigen::Vector3f nrm(input.normal->at(x, y, 0), input.normal->at(x, y, 1), input.normal->at(x, y, 2));
            if (nrm.squaredNorm() > 0) {
              ++with_depth;
              z += input.height->at(x, y);
              nsum += nrm;
            }
            const float* pi = &probabilities[(size_t(y) * size_t(w) + size_t(x)) * mm];
            for (size_t l = 0; l < mm; ++l) pb[l] += pi[l];
          }
        for (int c = 0; c < 3; ++c) rgb.at(bx, by, c) = uint8_t(std::lround(colour[c] / float(count)));
        for (size_t l = 0; l < mm; ++l) pb[l] /= float(count);
        if (with_depth > 0) {
          height.at(bx, by) = z / float(with_depth);
          const float len = nsum.norm();
          if (len > 1e-6f)
            for (int c = 0; c < 3; ++c) normal.at(bx, by, c) = nsum[c] / len;
        }
      }
  });
  DenseCrfOptions coarse = options;
  coarse.position_scale_px /= factor;
  coarse.smoothness_scale_px /= factor;
  coarse.iterations = options.iterations - 1;
  Result<DenseCrf> crf = DenseCrf::Create({&rgb, &height, &normal}, coarse);
  if (!crf.ok()) return crf.status();
  const std::vector<float> q = crf->MeanField(p, m);
  std::vector<float> messages;
  crf->Messages(q, m, false, &messages);
  // The last update per pixel, as MeanField's: Q_i(l) ~ exp(-psi_u,i(l) + message of its block).
  std::vector<float> out(n * mm);
  const float floor = float(options.probability_floor);
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& range) {
    std::vector<float> unary(mm);
    for (int y = range.begin(); y < range.end(); ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * size_t(w) + size_t(x);
        NegLogUnary(&probabilities[i * mm], m, floor, unary.data(), &out[i * mm]);
        UpdatePixel(unary.data(), &messages[(size_t(y / factor) * size_t(cw) + size_t(x / factor)) * mm], m, &out[i * mm]);
      }
  });
  return out;
}

}  // namespace semvox
