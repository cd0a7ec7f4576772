#include "objects/permutohedral.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace semvox {
namespace {

// Open-addressing hash table from lattice keys (the first d of the d+1 integer coordinates; the last one
// is minus their sum) to dense vertex indices.
class KeyTable {
 public:
  KeyTable(int d, size_t expected) : d_(d) {
    size_t cap = 64;
    while (cap < 2 * expected) cap *= 2;
    slots_.assign(cap, -1);
    keys_.reserve(expected * size_t(d));
  }
  // Index of `key`, inserted when absent and `insert`; -1 when absent and not inserting.
  int32_t Find(const int16_t* key, bool insert) {
    if (insert && 2 * (size() + 1) > slots_.size()) Grow();
    const size_t mask = slots_.size() - 1;
    size_t h = Hash(key) & mask;
    while (true) {
      const int32_t s = slots_[h];
      if (s < 0) {
        if (!insert) return -1;
        slots_[h] = int32_t(size());
        keys_.insert(keys_.end(), key, key + d_);
        return slots_[h];
      }
      if (std::memcmp(&keys_[size_t(s) * size_t(d_)], key, sizeof(int16_t) * size_t(d_)) == 0) return s;
      h = (h + 1) & mask;
    }
  }
  size_t size() const { return keys_.size() / size_t(d_); }
  const int16_t* key(size_t i) const { return &keys_[i * size_t(d_)]; }

 private:
  size_t Hash(const int16_t* key) const {
    size_t h = 0;
    for (int i = 0; i < d_; ++i) h = (h + size_t(uint16_t(key[i]))) * 2531011u;
    return h ^ (h >> 17);
  }
  void Grow() {
    std::vector<int32_t> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, -1);
    const size_t mask = slots_.size() - 1;
    for (size_t i = 0; i < size(); ++i) {
      size_t h = Hash(key(i)) & mask;
      while (slots_[h] >= 0) h = (h + 1) & mask;
      slots_[h] = int32_t(i);
    }
  }
  int d_;
  std::vector<int32_t> slots_;
  std::vector<int16_t> keys_;
};

// The splat of vertices [begin, end) as a gather: vertex v's m values (M = 0: m at run time) are the sum over
// its entries k (ascending) of barycentric[k] times point k / (d+1)'s values.
template <int M>
void SplatVertices(const int32_t* start, const int32_t* entry, const double* barycentric, size_t begin, size_t end,
                   const float* in, int m_runtime, int d1, double* values) {
  const size_t m = size_t(M > 0 ? M : m_runtime);
  for (size_t v = begin; v < end; ++v) {
    double* dst = values + v * m;
    for (int32_t e = start[v]; e < start[v + 1]; ++e) {
      const size_t k = size_t(entry[e]);
      const float* src = in + (k / size_t(d1)) * m;
      const double w = barycentric[k];
      for (size_t c = 0; c < m; ++c) dst[c] += w * src[c];
    }
  }
}

// The slice of points [begin, end): m values (M = 0: m at run time) per point, the sum over its d + 1
// vertices of barycentric * norm times the vertex's values.
template <int M>
void SlicePoints(const int32_t* offset, const double* barycentric, double norm, int begin, int end, int d1,
                 const double* values, int m_runtime, float* out) {
  const size_t m = size_t(M > 0 ? M : m_runtime);
  double acc[M > 0 ? M : 1];
  std::vector<double> acc_runtime(M > 0 ? 0 : m);
  double* a = M > 0 ? acc : acc_runtime.data();
  for (int p = begin; p < end; ++p) {
    for (size_t c = 0; c < m; ++c) a[c] = 0.0;
    for (int r = 0; r < d1; ++r) {
      const size_t k = size_t(p) * size_t(d1) + size_t(r);
      const double* src = values + size_t(offset[k]) * m;
      const double w = barycentric[k] * norm;
      for (size_t c = 0; c < m; ++c) a[c] += w * src[c];
    }
    float* dst = out + size_t(p) * m;
    for (size_t c = 0; c < m; ++c) dst[c] = float(a[c]);
  }
}

// Embeds points [begin, end) (Build's per-point step): their simplex corners' keys (d + 1 keys of d
// coordinates per point) and barycentric weights. D = d at compile time (0: d at run time, d <= 16).
template <int D>
void EmbedPoints(const float* features, int begin, int end, int d_runtime, const double* scale, int16_t* keys,
                 double* barycentric, std::atomic<bool>* out_of_range_flag) {
  const int d = D > 0 ? D : d_runtime;
  const int d1 = d + 1;
  std::atomic<bool>& out_of_range = *out_of_range_flag;
  double elevated[17], bary[18];
  int rem0[17], rank[17];
  for (int p = begin; p < end; ++p) {
    const float* f = features + size_t(p) * size_t(d);
    // Elevate: E f with E's columns (1, .., 1, -(i+1), 0, ..) / sqrt((i+1)(i+2)).
    double sm = 0;
    for (int j = d; j > 0; --j) {
      const double cf = double(f[j - 1]) * scale[j - 1];
      elevated[j] = sm - j * cf;
      sm += cf;
    }
    elevated[0] = sm;
    for (int i = 0; i <= d; ++i)
      if (!(std::abs(elevated[i]) < 28000.0)) out_of_range = true;  // Keys are int16 (NaN fails too); dilation moves a coordinate by <= 2 r d <= 2048.
    if (out_of_range) continue;
    // Closest remainder-0 point (all coordinates multiples of d+1), then the rank of every coordinate's
    // difference: the permutation that identifies the enclosing simplex.
    int sum = 0;
    for (int i = 0; i <= d; ++i) {
      const double v = elevated[i] / d1;
      const int up = int(std::ceil(v)) * d1, down = int(std::floor(v)) * d1;
      rem0[i] = (up - elevated[i] < elevated[i] - down) ? up : down;
      sum += rem0[i] / d1;
    }
    std::fill(rank, rank + d1, 0);
    for (int i = 0; i < d; ++i) {
      const double di = elevated[i] - rem0[i];
      for (int j = i + 1; j <= d; ++j) {
        if (di < elevated[j] - rem0[j]) ++rank[i];
        else ++rank[j];
      }
    }
    // Off the hyperplane (coordinates do not sum to 0): move the largest / smallest ones.
    if (sum > 0) {
      for (int i = 0; i <= d; ++i) {
        if (rank[i] >= d1 - sum) { rem0[i] -= d1; rank[i] += sum - d1; }
        else rank[i] += sum;
      }
    } else if (sum < 0) {
      for (int i = 0; i <= d; ++i) {
        if (rank[i] < -sum) { rem0[i] += d1; rank[i] += d1 + sum; }
        else rank[i] += sum;
      }
    }
    // Barycentric coordinates of the point in its simplex.
    std::fill(bary, bary + d1 + 1, 0.0);
    for (int i = 0; i <= d; ++i) {
      const double v = (elevated[i] - rem0[i]) / d1;
      bary[d - rank[i]] += v;
      bary[d + 1 - rank[i]] -= v;
    }
    bary[0] += 1.0 + bary[d1];
    // Vertex r of the simplex: rem0 + the canonical simplex's vertex r permuted by rank.
    for (int r = 0; r <= d; ++r) {
      int16_t* key = &keys[(size_t(p) * size_t(d1) + size_t(r)) * size_t(d)];
      for (int i = 0; i < d; ++i) {
        const int canonical = rank[i] <= d - r ? r : r - d1;
        key[i] = int16_t(rem0[i] + canonical);
      }
      barycentric[size_t(p) * size_t(d1) + size_t(r)] = bary[r];
    }
  }
}

}  // namespace

double PermutohedralLattice::RefinementScale(int refinement) { return std::sqrt((3.0 * refinement + 1.0) / 4.0); }

void PermutohedralLattice::Build(const float* features, int n, int d, int refinement) {
  if (d < 1 || d > 16 || n < 0) throw std::invalid_argument("PermutohedralLattice::Build: need n >= 0 and 1 <= d <= 16");
  if (refinement < 1 || refinement > kMaxRefinement)
    throw std::invalid_argument("PermutohedralLattice::Build: need 1 <= refinement <= " + std::to_string(kMaxRefinement));
  n_ = n;
  d_ = d;
  refinement_ = refinement;
  const int d1 = d + 1;
  offset_.assign(size_t(n) * size_t(d1), 0);
  barycentric_.assign(size_t(n) * size_t(d1), 0.f);

  // Scale of feature i so that the elevated point is sqrt(2/3) (d+1) times an isometric embedding of the
  // feature vector in the hyperplane sum x = 0 (Adams et al. 2010, Sec. 3.1): the blur and interpolation
  // then approximate a Gaussian of unit standard deviation in feature space.
  std::vector<double> scale(static_cast<size_t>(d));
  const double inv_std = std::sqrt(2.0 / 3.0) * d1 * RefinementScale(refinement);
  for (int i = 0; i < d; ++i) scale[size_t(i)] = inv_std / std::sqrt(double(i + 1) * double(i + 2));

  // Points are embedded in parallel, then their vertices are inserted sequentially (deterministic order).
  std::vector<int16_t> keys(size_t(n) * size_t(d1) * size_t(d));
  std::atomic<bool> out_of_range{false};
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 1024), [&](const tbb::blocked_range<int>& range) {
    switch (d) {
      case 2: EmbedPoints<2>(features, range.begin(), range.end(), d, scale.data(), keys.data(), barycentric_.data(), &out_of_range); break;
      case 3: EmbedPoints<3>(features, range.begin(), range.end(), d, scale.data(), keys.data(), barycentric_.data(), &out_of_range); break;
      case 5: EmbedPoints<5>(features, range.begin(), range.end(), d, scale.data(), keys.data(), barycentric_.data(), &out_of_range); break;
      default: EmbedPoints<0>(features, range.begin(), range.end(), d, scale.data(), keys.data(), barycentric_.data(), &out_of_range); break;
    }
  });

  if (out_of_range)
    throw std::invalid_argument("PermutohedralLattice::Build: features too large (|f| sqrt(2/3) (d+1) s must stay below 28000) or not finite");
  KeyTable table(d, size_t(n) * size_t(d1) / 2 + 16);
  for (size_t k = 0; k < size_t(n) * size_t(d1); ++k) offset_[k] = table.Find(&keys[k * size_t(d)], true);
  // A refined lattice blurs r steps along each direction: it needs the vertices the blur's paths pass through
  // (not only the corners of the points' simplices), else mass that leaves them is lost and the kernel is
  // truncated. Dilate the vertex set in the blur's order: before direction j's r passes, by r steps along j.
  if (refinement > 1) {
    std::vector<int16_t> key(static_cast<size_t>(d)), nb(static_cast<size_t>(d));
    for (int j = 0; j <= d; ++j)
      for (int pass = 0; pass < refinement; ++pass) {
        const size_t count = table.size();
        for (size_t v = 0; v < count; ++v) {
          std::memcpy(key.data(), table.key(v), sizeof(int16_t) * size_t(d));
          for (int sign = -1; sign <= 1; sign += 2) {
            for (int k = 0; k < d; ++k) nb[size_t(k)] = int16_t(key[size_t(k)] + sign);
            if (j < d) nb[size_t(j)] = int16_t(key[size_t(j)] - sign * d);
            table.Find(nb.data(), true);
          }
        }
      }
  }
  num_vertices_ = int(table.size());
  // The splat's gather lists (counting sort of the entries by vertex, stable: ascending k per vertex).
  {
    const size_t entries = size_t(n) * size_t(d1);
    splat_start_.assign(size_t(num_vertices_) + 1, 0);
    for (size_t k = 0; k < entries; ++k) ++splat_start_[size_t(offset_[k]) + 1];
    for (size_t v = 0; v < size_t(num_vertices_); ++v) splat_start_[v + 1] += splat_start_[v];
    splat_entry_.resize(entries);
    std::vector<int32_t> fill(splat_start_.begin(), splat_start_.end() - 1);
    for (size_t k = 0; k < entries; ++k) splat_entry_[size_t(fill[size_t(offset_[k])]++)] = int32_t(k);
  }

  // Neighbours along each lattice direction j: key + 1 - (d+1) e_j and key - 1 + (d+1) e_j (for j = d the
  // stored coordinates all move by +-1).
  const size_t L = size_t(num_vertices_);
  neighbour_minus_.assign(size_t(d1) * L, -1);
  neighbour_plus_.assign(size_t(d1) * L, -1);
  std::vector<int16_t> n1(static_cast<size_t>(d1)), n2(static_cast<size_t>(d1));
  for (int j = 0; j <= d; ++j) {
    for (size_t v = 0; v < L; ++v) {
      const int16_t* key = table.key(v);
      for (int k = 0; k < d; ++k) {
        n1[size_t(k)] = int16_t(key[k] + 1);
        n2[size_t(k)] = int16_t(key[k] - 1);
      }
      if (j < d) {
        n1[size_t(j)] = int16_t(key[j] - d);
        n2[size_t(j)] = int16_t(key[j] + d);
      }
      neighbour_plus_[size_t(j) * L + v] = table.Find(n1.data(), false);
      neighbour_minus_[size_t(j) * L + v] = table.Find(n2.data(), false);
    }
  }
}

void PermutohedralLattice::Filter(const float* in, int m, std::vector<float>* out) const {
  const int d1 = d_ + 1;
  const size_t L = size_t(num_vertices_);
  // Vertex values in double: a refined lattice blurs `refinement` times along each direction, and the
  // mean-field normaliser divides two filtered sums.
  std::vector<double> values(L * size_t(m), 0.0), next(L * size_t(m), 0.0);
  // Splat, as a gather per vertex (parallel over vertices): each vertex adds its entries in ascending
  // point order, exactly the sums of a sequential splat over the points.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, L, 4096), [&](const tbb::blocked_range<size_t>& range) {
    switch (m) {
      case 1: SplatVertices<1>(splat_start_.data(), splat_entry_.data(), barycentric_.data(), range.begin(), range.end(), in, m, d1, values.data()); break;
      case 2: SplatVertices<2>(splat_start_.data(), splat_entry_.data(), barycentric_.data(), range.begin(), range.end(), in, m, d1, values.data()); break;
      case 3: SplatVertices<3>(splat_start_.data(), splat_entry_.data(), barycentric_.data(), range.begin(), range.end(), in, m, d1, values.data()); break;
      default: SplatVertices<0>(splat_start_.data(), splat_entry_.data(), barycentric_.data(), range.begin(), range.end(), in, m, d1, values.data()); break;
    }
  });
  // Blur with [1 2 1] / 4, `refinement` times along each of the d+1 directions (mass preserving; missing
  // neighbours are 0).
  for (int j = 0; j < d1; ++j) {
    const int32_t* minus = &neighbour_minus_[size_t(j) * L];
    const int32_t* plus = &neighbour_plus_[size_t(j) * L];
    for (int pass = 0; pass < refinement_; ++pass) {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, L, 4096), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t v = range.begin(); v < range.end(); ++v) {
          const double* self = &values[v * size_t(m)];
          const double* a = minus[v] >= 0 ? &values[size_t(minus[v]) * size_t(m)] : nullptr;
          const double* b = plus[v] >= 0 ? &values[size_t(plus[v]) * size_t(m)] : nullptr;
          double* dst = &next[v * size_t(m)];
          for (int c = 0; c < m; ++c) dst[c] = 0.5 * self[c] + 0.25 * ((a ? a[c] : 0.0) + (b ? b[c] : 0.0));
        }
      });
      values.swap(next);
    }
  }
  // Slice, scaled so that a uniform density rho of points gives rho (2 pi)^{d/2}, the integral of the unit
  // Gaussian: one lattice vertex holds the mass of (3/2)^{d/2} / sqrt(d+1) / s^d feature-space volume (the
  // lattice (d+1) A*_d has covolume (d+1)^d / sqrt(d+1), shrunk by the elevation scale sqrt(2/3) (d+1) s
  // per axis).
  const double norm = std::pow(4.0 * M_PI / 3.0, 0.5 * d_) * std::sqrt(double(d1)) * std::pow(RefinementScale(refinement_), d_);
  out->assign(size_t(n_) * size_t(m), 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, n_, 1024), [&](const tbb::blocked_range<int>& range) {
    const int32_t* offset = offset_.data();
    const double* bary = barycentric_.data();
    switch (m) {
      case 1: SlicePoints<1>(offset, bary, norm, range.begin(), range.end(), d1, values.data(), m, out->data()); break;
      case 2: SlicePoints<2>(offset, bary, norm, range.begin(), range.end(), d1, values.data(), m, out->data()); break;
      case 3: SlicePoints<3>(offset, bary, norm, range.begin(), range.end(), d1, values.data(), m, out->data()); break;
      default: SlicePoints<0>(offset, bary, norm, range.begin(), range.end(), d1, values.data(), m, out->data()); break;
    }
  });
}

}  // namespace semvox
