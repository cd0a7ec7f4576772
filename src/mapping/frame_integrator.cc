#include "mapping/frame_integrator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "mapping/lane_traversal.h"
#include "mapping/ray_traversal.h"

namespace semvox {
namespace {

// Cell states in the frame's dense grid. Free cells are written during the (parallel) traversal, occupied
// ones afterwards, so that "occupied wins" needs no read-modify-write: every write is a plain store of a
// constant.
constexpr uint8_t kFreeCell = 1, kOccupiedCell = 2;

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

// Sets up the traversal from `origin` to `end` as TraverseGrid<true> does (mapping/lane_traversal.h); returns
// false when the ray visits nothing at all (origin and end in one cell). Otherwise the origin cell
// (`ray->idx`) is the first cell visited and the lane steps from there. Inside-grid variant: the caller
// guarantees the kInsideMargin around all ray ends.
inline bool SetUpLane(const Eigen::Vector3f& origin, const Eigen::Vector3f& end, double resolution,
                      const int grid_origin_key[3], const int64_t stride[3], LaneRay* ray) {
  const double inv = 1.0 / resolution;
  int64_t cur[3], ke[3];
  for (int i = 0; i < 3; ++i) {
    cur[i] = int64_t(std::floor(origin[i] * inv)) + kKeyOffset - grid_origin_key[i];
    ke[i] = int64_t(std::floor(end[i] * inv)) + kKeyOffset - grid_origin_key[i];
  }
  if (cur[0] == ke[0] && cur[1] == ke[1] && cur[2] == ke[2]) return false;
  SetUpLaneRay(origin, end, cur, ke, resolution, grid_origin_key, stride, ray);
  return true;
}

// Every cell a ray enters becomes free (unless already marked).
inline __attribute__((always_inline)) bool MarkFree(uint8_t* c) {
  std::atomic_ref<uint8_t> cell(*c);
  if (cell.load(std::memory_order_relaxed) == 0) cell.store(kFreeCell, std::memory_order_relaxed);
  return true;
}

__attribute__((target("avx2"))) void TraverseLanesAvx2(const LaneRay* rays, size_t count, uint8_t* cells) {
  TraverseLanes<4>(rays, count, cells, MarkFree);
}
void TraverseLanesSse2(const LaneRay* rays, size_t count, uint8_t* cells) { TraverseLanes<2>(rays, count, cells, MarkFree); }

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
  std::vector<uint8_t> cells(size_t(dim[0]) * dim[1] * dim[2], 0);
  auto index = [&](int64_t kx, int64_t ky, int64_t kz) {
    return (size_t(kz - lo[2]) * dim[1] + size_t(ky - lo[1])) * dim[0] + size_t(kx - lo[0]);
  };

  // 2. Free cells: rays in parallel, set up one by one and stepped several at a time (TraverseLanes);
  // threads store the constant kFreeCell into the shared grid (a grid whose first cell has key lo).
  const int grid_key[3] = {int(lo[0]), int(lo[1]), int(lo[2])};
  const int64_t stride[3] = {1, dim[0], dim[0] * dim[1]};
  static const bool avx2 = __builtin_cpu_supports("avx2");
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<LaneRay> lanes;
    lanes.reserve(r.size());
    bool origin_visited = false;
    for (size_t j = r.begin(); j != r.end(); ++j) {
      const Eigen::Vector3f& e = ends[j];
      // computeRayKeys gives nothing for an end outside the key range.
      if (!(KeyIndexInRange(key_of(e[0])) && KeyIndexInRange(key_of(e[1])) && KeyIndexInRange(key_of(e[2]))))
        continue;
      LaneRay ray;
      if (!SetUpLane(origin, e, resolution, grid_key, stride, &ray)) continue;
      if (!origin_visited) {  // Every ray starts in the origin's cell: mark it once.
        std::atomic_ref<uint8_t>(cells[ray.idx]).store(kFreeCell, std::memory_order_relaxed);
        origin_visited = true;
      }
      lanes.push_back(ray);
    }
    if (avx2) TraverseLanesAvx2(lanes.data(), lanes.size(), cells.data());
    else TraverseLanesSse2(lanes.data(), lanes.size(), cells.data());
  });
  // 3. Occupied cells: the end cell of every ray that ended within range (a cell both free and occupied is
  // occupied). After the traversal, so that these stores win.
  for (size_t j = 0; j < n; ++j) {
    if (!in_range[j]) continue;
    const Eigen::Vector3f& e = ends[j];
    const int64_t kx = key_of(e[0]), ky = key_of(e[1]), kz = key_of(e[2]);
    if (KeyIndexInRange(kx) && KeyIndexInRange(ky) && KeyIndexInRange(kz)) cells[index(kx, ky, kz)] = kOccupiedCell;
  }

  // 4. Collect keys in grid order (z, then y, then x).
  for (int64_t kz = 0; kz < dim[2]; ++kz)
    for (int64_t ky = 0; ky < dim[1]; ++ky) {
      const uint8_t* row = &cells[(size_t(kz) * dim[1] + size_t(ky)) * dim[0]];
      for (int64_t kx = 0; kx < dim[0]; ++kx) {
        if (!row[kx]) continue;
        const VoxelKey k{uint16_t(lo[0] + kx), uint16_t(lo[1] + ky), uint16_t(lo[2] + kz)};
        (row[kx] == kOccupiedCell ? out.occupied : out.free).push_back(k);
      }
    }
  return out;
}

}  // namespace semvox
