#include "mapping/frame_integrator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <cmath>

#include "mapping/ray_traversal.h"

namespace semvox {
namespace {

constexpr uint8_t kFreeBit = 1, kOccupiedBit = 2;

// OctoMap's point3d::norm(): float sum of squares, square root in double.
double OctomapNorm(const Eigen::Vector3f& d) {
  const float sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  return std::sqrt(double(sq));
}

// Where the ray actually ends: the end point, or the point at max range (OctoMap's computeUpdate).
Eigen::Vector3f RayEnd(const Eigen::Vector3f& origin, const Eigen::Vector3f& p, double max_range, bool* in_range) {
  const Eigen::Vector3f d(p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]);
  *in_range = max_range < 0.0 || OctomapNorm(d) <= max_range;
  if (*in_range) return p;
  Eigen::Vector3f dir = d;
  const double len = OctomapNorm(dir);
  if (len > 0.0) dir /= float(len);  // point3d::normalized()
  const Eigen::Vector3f step(dir[0] * float(max_range), dir[1] * float(max_range), dir[2] * float(max_range));
  return Eigen::Vector3f(origin[0] + step[0], origin[1] + step[1], origin[2] + step[2]);
}

}  // namespace

FrameUpdate IntegrateFrame(const Eigen::Vector3f& origin, const std::vector<Eigen::Vector3f>& end_points,
                           double resolution, double max_range_m) {
  FrameUpdate out;
  const size_t n = end_points.size();
  if (n == 0) return out;
  const double inv = 1.0 / resolution;
  auto key_of = [&](float c) { return int64_t(std::floor(inv * double(c))) + kKeyOffset; };

  // 1. Key bounds of all ray ends (the bitmap covers every key a ray can touch).
  std::vector<Eigen::Vector3f> ends(n);
  std::vector<uint8_t> in_range(n);
  struct Bounds {
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    void Add(int64_t k, int i) { lo[i] = std::min(lo[i], k), hi[i] = std::max(hi[i], k); }
    void Merge(const Bounds& o) {
      for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], o.lo[i]), hi[i] = std::max(hi[i], o.hi[i]);
    }
  };
  Bounds init;
  for (int i = 0; i < 3; ++i) init.Add(key_of(origin[i]), i);
  const Bounds b = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 4096), init,
      [&](const tbb::blocked_range<size_t>& r, Bounds acc) {
        for (size_t j = r.begin(); j != r.end(); ++j) {
          bool ok;
          ends[j] = RayEnd(origin, end_points[j], max_range_m, &ok);
          in_range[j] = ok;
          for (int i = 0; i < 3; ++i) acc.Add(key_of(ends[j][i]), i);
        }
        return acc;
      },
      [](Bounds a, const Bounds& c) { a.Merge(c); return a; });
  int64_t lo[3], dim[3];
  for (int i = 0; i < 3; ++i) {
    // A margin around all ray ends: OctoMap's traversal can overshoot the end cell by a step before its
    // distance test stops it, and TraverseGrid<true> relies on the margin.
    lo[i] = std::max<int64_t>(0, b.lo[i] - kInsideMargin);
    dim[i] = std::min<int64_t>(65535, b.hi[i] + kInsideMargin) - lo[i] + 1;
  }
  std::vector<uint8_t> bits(size_t(dim[0]) * dim[1] * dim[2], 0);
  auto index = [&](int64_t kx, int64_t ky, int64_t kz) {
    return (size_t(kz - lo[2]) * dim[1] + size_t(ky - lo[1])) * dim[0] + size_t(kx - lo[0]);
  };

  // 2. Rays in parallel; each thread ORs bits into the shared bitmap (a grid whose first cell has key lo).
  const int grid_key[3] = {int(lo[0]), int(lo[1]), int(lo[2])};
  const int grid_dims[3] = {int(dim[0]), int(dim[1]), int(dim[2])};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t j = r.begin(); j != r.end(); ++j) {
      const Eigen::Vector3f& e = ends[j];
      const int64_t kx = key_of(e[0]), ky = key_of(e[1]), kz = key_of(e[2]);
      // computeRayKeys gives nothing for an end outside the key range; the end voxel is occupied only when
      // the end point was within range.
      if (!(KeyIndexInRange(kx) && KeyIndexInRange(ky) && KeyIndexInRange(kz))) continue;
      if (in_range[j])
        std::atomic_ref<uint8_t>(bits[index(kx, ky, kz)]).fetch_or(kOccupiedBit, std::memory_order_relaxed);
      TraverseGrid<true>(origin, e, resolution, grid_key, grid_dims, [&](size_t idx) {
        uint8_t& cell = bits[idx];
        if (!(std::atomic_ref<uint8_t>(cell).load(std::memory_order_relaxed) & kFreeBit))
          std::atomic_ref<uint8_t>(cell).fetch_or(kFreeBit, std::memory_order_relaxed);
        return true;
      });
    }
  });

  // 3. Collect keys in grid order (z, then y, then x).
  for (int64_t kz = 0; kz < dim[2]; ++kz)
    for (int64_t ky = 0; ky < dim[1]; ++ky) {
      const uint8_t* row = &bits[(size_t(kz) * dim[1] + size_t(ky)) * dim[0]];
      for (int64_t kx = 0; kx < dim[0]; ++kx) {
        if (!row[kx]) continue;
        const VoxelKey k{uint16_t(lo[0] + kx), uint16_t(lo[1] + ky), uint16_t(lo[2] + kz)};
        (row[kx] & kOccupiedBit ? out.occupied : out.free).push_back(k);
      }
    }
  return out;
}

}  // namespace semvox
