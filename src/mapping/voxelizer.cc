#include "mapping/voxelizer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/log.h"
#include "mapping/cloud_geometry.h"
#include "mapping/lane_traversal.h"
#include "mapping/ray_traversal.h"

namespace semvox {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

// Concurrent writers only ever raise a voxel's state to the same value, so relaxed atomics suffice.
inline void StoreState(uint8_t* cell, VoxelState s) {
  std::atomic_ref<uint8_t>(*cell).store(uint8_t(s), std::memory_order_relaxed);
}
inline VoxelState LoadState(const uint8_t* cell) {
  return VoxelState(std::atomic_ref<uint8_t>(*const_cast<uint8_t*>(cell)).load(std::memory_order_relaxed));
}

// Separating-axis test of a triangle against an axis-aligned box centred at the origin with half size h
// (Akenine-Möller 2001).
bool TriangleOverlapsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const Eigen::Vector3d& h) {
  const Eigen::Vector3d e[3] = {b - a, c - b, a - c};
  const Eigen::Vector3d v[3] = {a, b, c};
  for (int i = 0; i < 3; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      u[axis] = 1.0;
      const Eigen::Vector3d l = u.cross(e[i]);
      const double p0 = l.dot(v[0]), p1 = l.dot(v[1]), p2 = l.dot(v[2]);
      const double r = h.x() * std::fabs(l.x()) + h.y() * std::fabs(l.y()) + h.z() * std::fabs(l.z());
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (std::min({a[axis], b[axis], c[axis]}) > h[axis] || std::max({a[axis], b[axis], c[axis]}) < -h[axis]) return false;
  }
  const Eigen::Vector3d n = e[0].cross(e[1]);
  const double d = n.dot(a);
  const double r = h.x() * std::fabs(n.x()) + h.y() * std::fabs(n.y()) + h.z() * std::fabs(n.z());
  return std::fabs(d) <= r;
}

// Dominant lowest / highest horizontal surfaces from (z, weight) samples of near-horizontal elements.
// Area histogram of horizontal surfaces over height, in bins of `bin_m`.
struct HeightHistogram {
  double zmin = 0, bin = 0.05;
  std::vector<double> area, zsum;
  HeightHistogram(const std::vector<std::pair<double, double>>& samples, double zlo, double zhi, double bin_m)
      : zmin(zlo), bin(bin_m) {
    const int nb = int(std::floor((zhi - zlo) / bin_m)) + 1;
    area.assign(nb, 0.0);
    zsum.assign(nb, 0.0);
    for (const auto& [z, w] : samples) {
      const int b = std::clamp(int(std::floor((z - zmin) / bin_m)), 0, nb - 1);
      area[b] += w;
      zsum[b] += w * z;
    }
  }
  int size() const { return int(area.size()); }
  double Centre(int b) const { return zmin + (b + 0.5) * bin; }
  // Area-weighted height over the bin and its neighbours (a plane straddling a bin edge).
  double Refined(int b) const {
    double a = 0, s = 0;
    for (int k = std::max(0, b - 1); k <= std::min(size() - 1, b + 1); ++k) a += area[k], s += zsum[k];
    return s / a;
  }
};

// First occupied voxel along a ray within `range` (cells), or -1.
double DistanceToOccupied(const VoxelGrid& grid, const Eigen::Vector3d& from, const Eigen::Vector3d& dir, double range) {
  const Eigen::Vector3f o = from.cast<float>();
  const Eigen::Vector3f e = (from + dir * range).cast<float>();
  double hit = -1;
  const int okey[3] = {grid.origin_key()[0], grid.origin_key()[1], grid.origin_key()[2]};
  const int dims[3] = {grid.dims()[0], grid.dims()[1], grid.dims()[2]};
  TraverseGrid(o, e, grid.resolution(), okey, dims, [&](size_t idx) {
    if (grid.state(idx) != VoxelState::kOccupied) return true;
    const auto c = grid.Cell(idx);
    hit = (grid.CellCenter(c[0], c[1], c[2]) - from).norm();
    return false;
  });
  return hit;
}

// Free-space rays stepped several at a time (mapping/lane_traversal.h; frame_integrator.cc marks every cell,
// these stop at the first occupied one), each exactly as TraverseGrid<true> steps it.
// TraverseGrid<true> needs kInsideMargin cells around both ends so that no ray leaves the grid before its step
// budget or distance test stops it; a free-space ray needs none: it ends at an occupied target voxel inside
// the grid (the segment runs half a voxel past the target's centre, so the traversal enters the target's cell
// unless an earlier occupied voxel stops it), never leaves the grid on the way, and reaches the target after
// exactly the Manhattan distance in cells, within the budget (the end cell is at most one cell past the target
// on each axis). The end cell must lie in the grid (its index is compared with the cells entered).

// What a position's rays share: the origin (float, as TraverseGrid takes it) and its cell.
struct FreeRayOrigin {
  Eigen::Vector3f origin;
  int64_t cur[3];
  int64_t idx;
};

inline FreeRayOrigin SetUpFreeRayOrigin(const Eigen::Vector3f& origin, double resolution, const int grid_origin_key[3],
                                        const int64_t stride[3]) {
  FreeRayOrigin o;
  o.origin = origin;
  const double inv = 1.0 / resolution;
  for (int i = 0; i < 3; ++i) o.cur[i] = int64_t(std::floor(origin[i] * inv)) + kKeyOffset - grid_origin_key[i];
  o.idx = o.cur[2] * stride[2] + o.cur[1] * stride[1] + o.cur[0];
  return o;
}

enum class FreeRaySetUp { kLane, kEmpty, kOutside };

// Sets up the traversal from `o` to `end` with TraverseGrid<true>'s arithmetic. kEmpty: the ray visits
// nothing (origin and end in one cell); kOutside: the end cell is outside the grid (TraverseGrid's general
// loop takes the ray). A lane steps from the origin's cell, which the caller visits.
inline FreeRaySetUp SetUpFreeRay(const FreeRayOrigin& o, const Eigen::Vector3f& end, double resolution,
                                 const int grid_origin_key[3], const int dims[3], const int64_t stride[3],
                                 LaneRay* ray) {
  const double inv = 1.0 / resolution;
  int64_t ke[3];
  for (int i = 0; i < 3; ++i) {
    ke[i] = int64_t(std::floor(end[i] * inv)) + kKeyOffset - grid_origin_key[i];
    if (ke[i] < 0 || ke[i] >= dims[i]) return FreeRaySetUp::kOutside;
  }
  if (o.cur[0] == ke[0] && o.cur[1] == ke[1] && o.cur[2] == ke[2]) return FreeRaySetUp::kEmpty;
  SetUpLaneRay(o.origin, end, o.cur, ke, resolution, grid_origin_key, stride, ray);
  return FreeRaySetUp::kLane;
}

// A free-space ray ends at the first occupied cell; unknown cells on the way become free.
inline __attribute__((always_inline)) bool CastFree(uint8_t* cell) {
  const VoxelState s = LoadState(cell);
  if (s == VoxelState::kOccupied) return false;
  if (s == VoxelState::kUnknown) StoreState(cell, VoxelState::kFree);
  return true;
}

__attribute__((target("avx2"))) void CastFreeLanesAvx2(const LaneRay* rays, size_t count, uint8_t* cells) {
  TraverseLanes<4>(rays, count, cells, CastFree);
}
void CastFreeLanesSse2(const LaneRay* rays, size_t count, uint8_t* cells) { TraverseLanes<2>(rays, count, cells, CastFree); }

}  // namespace

// Floor: the lowest bin of upward-facing area holding at least 30% of the largest such bin. Ceiling: the
// highest bin of downward-facing area with at least 10% of the floor's area, far enough above the floor.
// Orientation tells a floor slab's top from its underside; clouds (unoriented normals) pass the same
// samples for both.
FloorCeiling DetectFloorCeiling(const std::vector<std::pair<double, double>>& up,
                                const std::vector<std::pair<double, double>>& down, double bin_m,
                                double min_floor_to_ceiling_m) {
  FloorCeiling fc;
  if (up.empty()) return fc;
  double zmin = up[0].first, zmax = zmin;
  for (const auto* v : {&up, &down})
    for (const auto& [z, w] : *v) zmin = std::min(zmin, z), zmax = std::max(zmax, z);
  const HeightHistogram hu(up, zmin, zmax, bin_m), hd(down, zmin, zmax, bin_m);
  const double peak = *std::max_element(hu.area.begin(), hu.area.end());
  if (peak <= 0) return fc;
  int fb = -1;
  for (int b = 0; b < hu.size(); ++b)
    if (hu.area[b] >= 0.3 * peak) { fb = b; break; }
  if (fb < 0) return fc;
  fc.floor_found = true;
  fc.floor_z = hu.Refined(fb);
  const double floor_area = hu.area[fb];
  for (int b = hd.size() - 1; b > fb; --b) {
    if (hd.Centre(b) - fc.floor_z < min_floor_to_ceiling_m) break;
    if (hd.area[b] >= 0.1 * floor_area) {
      fc.ceiling_found = true;
      fc.ceiling_z = hd.Refined(b);
      break;
    }
  }
  return fc;
}

bool VoxelizeOptions::Check(std::string* error) const { return CheckOptions(*this, Options(), error); }

Status PlanVoxelGrid(const Aabb& box, const VoxelizeOptions& options, VoxelGrid* grid) {
  const double res = options.voxel_size_m;
  std::array<int64_t, 3> lo, hi;
  for (int i = 0; i < 3; ++i) {
    lo[i] = CoordToKeyIndex(box.min[i], res) - 1;
    hi[i] = CoordToKeyIndex(box.max[i], res) + 1;
    if (!KeyIndexInRange(lo[i]) || !KeyIndexInRange(hi[i]))
      return Status::InvalidInput("the scene spans " + std::to_string(box.min[i]) + " .. " + std::to_string(box.max[i]) +
                                  " m on axis " + "xyz"[i] + ", beyond OctoMap's key range at " + std::to_string(res) +
                                  " m voxels (hint: check units with --scale, or use larger voxels)");
  }
  const std::array<int, 3> dims = {int(hi[0] - lo[0] + 1), int(hi[1] - lo[1] + 1), int(hi[2] - lo[2] + 1)};
  const double count = double(dims[0]) * dims[1] * dims[2];
  if (count > double(options.max_voxels))
    return Status::InvalidInput("the voxel grid would hold " + std::to_string(size_t(count)) + " voxels (" +
                                std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                                std::to_string(dims[2]) + ", about " + std::to_string(size_t(count * 4 / 1e6)) +
                                " MB), over max_voxels = " + std::to_string(options.max_voxels) +
                                " (hint: raise --max-voxels, use larger voxels, or check the units with --scale)");
  *grid = VoxelGrid(res, {int(lo[0]), int(lo[1]), int(lo[2])}, dims);
  return Status::Ok();
}

void VoxelizeMeshSurface(const Mesh& mesh, VoxelGrid* grid) {
  const double res = grid->resolution();
  // Half-open cells: each box is shifted down by a hair, [lo - eps, hi - eps], so a surface lying exactly
  // on a cell boundary belongs to the cell above it, as OctoMap's coordToKey (floor) assigns points, and
  // rounding in the cell centres cannot make such a surface miss both cells.
  const double eps = 1e-4 * res;
  const Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5 * res);
  uint8_t* state = grid->state_data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.faces.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t f = r.begin(); f != r.end(); ++f) {
      const Eigen::Vector3i& t = mesh.faces[f];
      const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                            c = mesh.vertices[t[2]].cast<double>();
      if ((b - a).cross(c - a).squaredNorm() <= 0.0) continue;  // Degenerate.
      const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
      const auto clo = grid->CellOf(lo + Eigen::Vector3d::Constant(eps)), chi = grid->CellOf(hi + Eigen::Vector3d::Constant(eps));
      for (int iz = std::max(0, clo[2]); iz <= std::min(grid->dims()[2] - 1, chi[2]); ++iz)
        for (int iy = std::max(0, clo[1]); iy <= std::min(grid->dims()[1] - 1, chi[1]); ++iy)
          for (int ix = std::max(0, clo[0]); ix <= std::min(grid->dims()[0] - 1, chi[0]); ++ix) {
            const size_t idx = grid->Index(ix, iy, iz);
            if (LoadState(state + idx) == VoxelState::kOccupied) continue;
            const Eigen::Vector3d centre = grid->CellCenter(ix, iy, iz) - Eigen::Vector3d::Constant(eps);
            if (TriangleOverlapsBox(a - centre, b - centre, c - centre, half)) StoreState(state + idx, VoxelState::kOccupied);
          }
    }
  });
}

void VoxelizeCloudSurface(const PointCloud& cloud, const std::vector<Eigen::Vector3f>& normals,
                          const std::vector<float>& spacing, VoxelGrid* grid) {
  const double res = grid->resolution();
  uint8_t* state = grid->state_data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cloud.points.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d p = cloud.points[i].cast<double>();
      auto mark = [&](const Eigen::Vector3d& q) {
        const auto c = grid->CellOf(q);
        if (grid->Contains(c[0], c[1], c[2])) StoreState(state + grid->Index(c[0], c[1], c[2]), VoxelState::kOccupied);
      };
      mark(p);
      const double radius = spacing.empty() ? 0.0 : std::min<double>(spacing[i], 3.0 * res);
      if (radius <= 0.5 * res || normals.empty()) continue;
      // Disc in the tangent plane, sampled at half-voxel steps.
      const Eigen::Vector3d n = normals[i].cast<double>();
      Eigen::Vector3d u = std::fabs(n.z()) < 0.9 ? n.cross(Eigen::Vector3d::UnitZ()) : n.cross(Eigen::Vector3d::UnitX());
      u.normalize();
      const Eigen::Vector3d v = n.cross(u);
      const double step = 0.5 * res;
      const int k = int(std::ceil(radius / step));
      for (int a = -k; a <= k; ++a)
        for (int b = -k; b <= k; ++b) {
          const double da = a * step, db = b * step;
          if (da * da + db * db <= radius * radius) mark(p + da * u + db * v);
        }
    }
  });
}

std::vector<uint32_t> PointVoxels(const std::vector<Eigen::Vector3f>& points, const VoxelGrid& grid) {
  std::vector<uint32_t> out(points.size(), UINT32_MAX);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto c = grid.CellOf(points[i].cast<double>());
      if (grid.Contains(c[0], c[1], c[2])) out[i] = uint32_t(grid.Index(c[0], c[1], c[2]));
    }
  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  if (!out.empty() && out.back() == UINT32_MAX) out.pop_back();
  return out;
}

size_t CastFreeSpace(const std::vector<Eigen::Vector3d>& positions, double max_range_m, VoxelGrid* grid,
                     const ProgressCallback& progress) {
  // The occupied voxels' centres, once for all positions (the occupied set does not change while casting:
  // rays only turn unknown voxels free).
  std::vector<Eigen::Vector3d> targets;
  for (size_t i = 0; i < grid->size(); ++i)
    if (grid->state(i) == VoxelState::kOccupied) {
      const auto cell = grid->Cell(i);
      targets.push_back(grid->CellCenter(cell[0], cell[1], cell[2]));
    }
  uint8_t* state = grid->state_data();
  const int okey[3] = {grid->origin_key()[0], grid->origin_key()[1], grid->origin_key()[2]};
  const int dims[3] = {grid->dims()[0], grid->dims()[1], grid->dims()[2]};
  const double res = grid->resolution();
  auto free_until_occupied = [state](size_t idx) {
    uint8_t* cellp = state + idx;
    const VoxelState s = LoadState(cellp);
    if (s == VoxelState::kOccupied) return false;
    if (s == VoxelState::kUnknown) StoreState(cellp, VoxelState::kFree);
    return true;
  };
  const double range_sq = max_range_m * max_range_m;
  const int64_t stride[3] = {1, dims[0], int64_t(dims[0]) * dims[1]};
  static const bool avx2 = __builtin_cpu_supports("avx2");
  std::atomic<size_t> rays{0};
  for (size_t pi = 0; pi < positions.size(); ++pi) {
    if (progress) progress(pi, positions.size());
    const Eigen::Vector3d& pos = positions[pi];
    const Eigen::Vector3f origin = pos.cast<float>();
    const auto oc = grid->CellOf(pos);
    if (grid->Contains(oc[0], oc[1], oc[2]) && grid->state(grid->Index(oc[0], oc[1], oc[2])) != VoxelState::kOccupied)
      StoreState(state + grid->Index(oc[0], oc[1], oc[2]), VoxelState::kFree);
    // The rays go to the lanes when the origin's cell as the traversal finds it (from the float origin; it may
    // differ from `oc` on a cell boundary) is in the grid and not occupied (an occupied one ends every ray at
    // once: TraverseGrid visits it first); otherwise TraverseGrid takes them.
    const FreeRayOrigin lane_origin = SetUpFreeRayOrigin(origin, res, okey, stride);
    bool lanes_ok = true;
    for (int i = 0; i < 3; ++i) lanes_ok &= lane_origin.cur[i] >= 0 && lane_origin.cur[i] < dims[i];
    lanes_ok = lanes_ok && LoadState(state + lane_origin.idx) != VoxelState::kOccupied;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, targets.size(), 2048), [&](const tbb::blocked_range<size_t>& r) {
      size_t local = 0;
      std::vector<LaneRay> lanes;
      lanes.reserve(r.size());
      for (size_t j = r.begin(); j != r.end(); ++j) {
        const Eigen::Vector3d& target = targets[j];
        if ((target - pos).squaredNorm() > range_sq) continue;
        ++local;
        // Extend the segment half a voxel past the target centre so the target cell is entered.
        const Eigen::Vector3d dir = (target - pos).normalized();
        const Eigen::Vector3f end = (target + dir * (0.5 * res)).cast<float>();
        LaneRay ray;
        const FreeRaySetUp setup = lanes_ok ? SetUpFreeRay(lane_origin, end, res, okey, dims, stride, &ray) : FreeRaySetUp::kOutside;
        if (setup == FreeRaySetUp::kLane) lanes.push_back(ray);
        else if (setup == FreeRaySetUp::kOutside) TraverseGrid(origin, end, res, okey, dims, free_until_occupied);
      }
      if (!lanes.empty()) free_until_occupied(size_t(lane_origin.idx));  // Every lane ray visits the origin's cell first.
      if (avx2) CastFreeLanesAvx2(lanes.data(), lanes.size(), state);
      else CastFreeLanesSse2(lanes.data(), lanes.size(), state);
      rays += local;
    });
  }
  if (progress) progress(positions.size(), positions.size());
  return rays.load();
}

Result<VoxelMap> Voxelize(const Scene& scene, const VoxelizeOptions& options, const ProgressCallback& progress) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput(error);
  VoxelMap map;
  Aabb box = scene.Bounds();
  if (!box.valid()) return Status::InvalidInput(FileError(scene.source_path, "scene has no geometry", ""));
  // Room for the scanner above the lowest surface even when the scan is flat (a single floor plane).
  box.max.z() = std::max<float>(box.max.z(), box.min.z() + float(options.scan_height_m + options.scan_clearance_m));
  SEMVOX_RETURN_IF_ERROR(PlanVoxelGrid(box, options, &map.grid));
  VoxelGrid& grid = map.grid;
  const double res = options.voxel_size_m;

  // 1. Surface voxels and horizontal-surface samples for floor / ceiling detection.
  auto t0 = Clock::now();
  const double cos_h = std::cos(options.horizontal_normal_deg * M_PI / 180.0);
  std::vector<std::pair<double, double>> up, down;  // (z, area) of upward / downward-facing surfaces.
  if (scene.is_mesh()) {
    VoxelizeMeshSurface(scene.mesh, &grid);
    map.exact_surface = true;
    for (const auto& t : scene.mesh.faces) {
      const Eigen::Vector3d a = scene.mesh.vertices[t[0]].cast<double>(), b = scene.mesh.vertices[t[1]].cast<double>(),
                            c = scene.mesh.vertices[t[2]].cast<double>();
      const Eigen::Vector3d n = (b - a).cross(c - a);
      const double area2 = n.norm();
      if (area2 <= 0) continue;
      const double nz = n.z() / area2, z = (a.z() + b.z() + c.z()) / 3.0;
      if (nz >= cos_h) up.push_back({z, 0.5 * area2});
      if (nz <= -cos_h) down.push_back({z, 0.5 * area2});
    }
    // Meshes with inconsistent winding: fall back to unoriented surfaces.
    if (up.empty() || down.empty()) {
      up.insert(up.end(), down.begin(), down.end());
      down = up;
    }
  } else {
    CloudGeometry geo = EstimateCloudGeometry(scene.cloud, options.cloud_normal_neighbors);
    const std::vector<Eigen::Vector3f>& normals = scene.cloud.normals.empty() ? geo.normals : scene.cloud.normals;
    VoxelizeCloudSurface(scene.cloud, normals, geo.spacing, &grid);
    map.point_voxels = PointVoxels(scene.cloud.points, grid);
    for (size_t i = 0; i < scene.cloud.points.size(); ++i)
      if (std::fabs(normals[i].z()) >= cos_h) {
        const double s = std::max<double>(geo.spacing[i], 1e-3);
        up.push_back({scene.cloud.points[i].z(), s * s});
      }
    down = up;  // PCA normals carry no orientation.
  }
  map.seconds_surface = Seconds(t0);
  const auto counts = grid.CountStates();
  if (counts[2] == 0)
    return Status::InvalidInput(FileError(scene.source_path, "no surface voxels (only degenerate triangles?)",
                                          "the input holds no usable surface"));

  // 2. Floor and ceiling.
  t0 = Clock::now();
  FloorCeiling fc = DetectFloorCeiling(up, down, res, options.min_floor_to_ceiling_m);
  map.floor_found = fc.floor_found;
  map.ceiling_found = fc.ceiling_found;
  map.floor_z = fc.floor_found ? fc.floor_z : box.min.z();
  map.ceiling_z = fc.ceiling_found ? fc.ceiling_z : box.max.z();
  if (!fc.floor_found)
    SEMVOX_WARN(scene.source_path << ": no floor found (no dominant horizontal surface); heights are relative to the "
                                     "lowest point, z = " << map.floor_z);
  if (!fc.ceiling_found)
    SEMVOX_INFO(scene.source_path << ": no ceiling found; using the top of the scan, z = " << map.ceiling_z);
  map.seconds_floor = Seconds(t0);

  if (!options.free_space) return map;  // Surfaces, floor and ceiling only.

  // 3. Scan positions: a grid at scanner height, clear of surfaces, above a floor, enclosed by surfaces.
  t0 = Clock::now();
  double z = map.floor_z + options.scan_height_m;
  if (map.ceiling_z - map.floor_z > 0.2 && z > map.ceiling_z - options.scan_clearance_m - res)
    z = 0.5 * (map.floor_z + map.ceiling_z);
  // A position's tests: a surface below (the floor, or furniture on it; without a detected floor this cannot
  // be required), and, with `require_enclosure`, enough horizontal rays that hit a surface (indoors).
  auto floor_and_enclosure = [&](const Eigen::Vector3d& p, bool require_enclosure) {
    if (map.floor_found && DistanceToOccupied(grid, p, -Eigen::Vector3d::UnitZ(), z - box.min.z() + 2 * res) < 0) return false;
    if (!require_enclosure) return true;
    int hits = 0;
    for (int d = 0; d < options.enclosure_directions; ++d) {
      const double ang = 2.0 * M_PI * d / options.enclosure_directions;
      hits += DistanceToOccupied(grid, p, Eigen::Vector3d(std::cos(ang), std::sin(ang), 0), options.max_range_m) >= 0;
    }
    return hits >= options.min_enclosed_fraction * options.enclosure_directions;
  };
  auto choose_positions = [&](double spacing, bool require_enclosure) {
    std::vector<Eigen::Vector3d> out;
    const int nx = std::max(1, int(std::floor((box.max.x() - box.min.x()) / spacing)) + 1);
    const int ny = std::max(1, int(std::floor((box.max.y() - box.min.y()) / spacing)) + 1);
    const double x0 = 0.5 * (box.min.x() + box.max.x()) - 0.5 * (nx - 1) * spacing;
    const double y0 = 0.5 * (box.min.y() + box.max.y()) - 0.5 * (ny - 1) * spacing;
    const int clear = int(std::ceil(options.scan_clearance_m / res));
    std::vector<char> keep(size_t(nx) * ny, 0);
    tbb::parallel_for(0, nx * ny, [&](int k) {
      const Eigen::Vector3d p(x0 + (k % nx) * spacing, y0 + (k / nx) * spacing, z);
      const auto c = grid.CellOf(p);
      if (!grid.Contains(c[0], c[1], c[2])) return;
      for (int dz = -clear; dz <= clear; ++dz)
        for (int dy = -clear; dy <= clear; ++dy)
          for (int dx = -clear; dx <= clear; ++dx) {
            if ((dx * dx + dy * dy + dz * dz) * res * res > options.scan_clearance_m * options.scan_clearance_m) continue;
            const int x = c[0] + dx, y = c[1] + dy, zz = c[2] + dz;
            if (grid.Contains(x, y, zz) && grid.state(grid.Index(x, y, zz)) == VoxelState::kOccupied) return;
          }
      if (floor_and_enclosure(p, require_enclosure)) keep[k] = 1;
    });
    for (int k = 0; k < nx * ny; ++k)
      if (keep[k]) out.emplace_back(x0 + (k % nx) * spacing, y0 + (k / nx) * spacing, z);
    return out;
  };
  // Pockets: 4-connected regions of cells at scanner height that are clear of occupied voxels (within
  // scan_clearance_m horizontally, in the layers scan_clearance_m above and below), still unknown, and next to
  // seen free space; each gets one position at its cell farthest from the occupied ones. Largest regions
  // first, ties by cell order.
  auto pocket_positions = [&]() {
    std::vector<Eigen::Vector3d> out;
    const auto d = grid.dims();
    const int cz = grid.CellOf(Eigen::Vector3d(box.min.x(), box.min.y(), z))[2];
    if (cz < 0 || cz >= d[2]) return out;
    const int band = std::max(1, int(std::ceil(options.scan_clearance_m / res)));
    const size_t W = size_t(d[0]), H = size_t(d[1]);
    // Chessboard distance (cells) to the nearest column with an occupied voxel in the band; the grid's
    // border counts as occupied.
    const int kFar = 1 << 20;
    std::vector<int> dist(W * H, kFar);
    tbb::parallel_for(size_t(0), H, [&](size_t y) {
      for (size_t x = 0; x < W; ++x) {
        bool occ = x == 0 || y == 0 || x + 1 == W || y + 1 == H;
        for (int zz = std::max(0, cz - band); zz <= std::min(d[2] - 1, cz + band) && !occ; ++zz)
          occ = grid.state(grid.Index(int(x), int(y), zz)) == VoxelState::kOccupied;
        if (occ) dist[y * W + x] = 0;
      }
    });
    for (size_t y = 0; y < H; ++y)
      for (size_t x = 0; x < W; ++x) {
        int& v = dist[y * W + x];
        if (x > 0) v = std::min(v, dist[y * W + x - 1] + 1);
        if (y > 0) {
          v = std::min(v, dist[(y - 1) * W + x] + 1);
          if (x > 0) v = std::min(v, dist[(y - 1) * W + x - 1] + 1);
          if (x + 1 < W) v = std::min(v, dist[(y - 1) * W + x + 1] + 1);
        }
      }
    for (size_t y = H; y-- > 0;)
      for (size_t x = W; x-- > 0;) {
        int& v = dist[y * W + x];
        if (x + 1 < W) v = std::min(v, dist[y * W + x + 1] + 1);
        if (y + 1 < H) {
          v = std::min(v, dist[(y + 1) * W + x] + 1);
          if (x + 1 < W) v = std::min(v, dist[(y + 1) * W + x + 1] + 1);
          if (x > 0) v = std::min(v, dist[(y + 1) * W + x - 1] + 1);
        }
      }
    // Clear: more than scan_clearance_m from every occupied column (the chessboard distance understates the
    // Euclidean one, so this is conservative); unseen: the voxel at scanner height is still unknown.
    const int min_cells = int(std::floor(options.scan_clearance_m / res)) + 1;
    auto pocket = [&](size_t i) {
      return dist[i] >= min_cells && grid.state(grid.Index(int(i % W), int(i / W), cz)) == VoxelState::kUnknown;
    };
    std::vector<int> component(W * H, -1);
    struct Region {
      size_t cells = 0, best = 0;
      bool reached = false;  // It borders seen free space (a closet seen in part through its door), unlike
                             // the sealed inside of a closed piece of furniture in a mesh.
    };
    std::vector<Region> regions;
    std::vector<size_t> queue;
    for (size_t i = 0; i < W * H; ++i) {
      if (component[i] >= 0 || !pocket(i)) continue;
      Region r;
      r.best = i;
      component[i] = int(regions.size());
      queue.assign(1, i);
      for (size_t head = 0; head < queue.size(); ++head) {
        const size_t q = queue[head];
        ++r.cells;
        if (dist[q] > dist[r.best]) r.best = q;
        const size_t qx = q % W, qy = q / W;
        const size_t nb[4] = {qx > 0 ? q - 1 : q, qx + 1 < W ? q + 1 : q, qy > 0 ? q - W : q, qy + 1 < H ? q + W : q};
        for (size_t n : nb) {
          if (n == q) continue;
          if (component[n] < 0 && pocket(n))
            component[n] = int(regions.size()), queue.push_back(n);
          else if (grid.state(grid.Index(int(n % W), int(n / W), cz)) == VoxelState::kFree)
            r.reached = true;
        }
      }
      regions.push_back(r);
    }
    std::vector<size_t> order(regions.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return regions[a].cells > regions[b].cells; });
    // A room no door of the model leads into (a plan's opening drawn as wall, a flat's part reached from the
    // stairwell) borders no seen free space either; it differs from the inside of a closed piece of furniture
    // by what stands over it: the ceiling, not a lid. Such a region gets a position when it holds a person's
    // floor area and the first surfaces straight above and below its most open cell are the detected ceiling
    // and floor.
    const double tolerance = options.sealed_room_tolerance_m;
    auto sealed_room = [&](const Region& r, const Eigen::Vector3d& p) {
      if (tolerance <= 0 || !map.floor_found || !map.ceiling_found) return false;
      if (double(r.cells) * res * res < options.min_sealed_room_m2) return false;
      const double up = DistanceToOccupied(grid, p, Eigen::Vector3d::UnitZ(), map.ceiling_z - z + 2 * tolerance);
      const double down = DistanceToOccupied(grid, p, -Eigen::Vector3d::UnitZ(), z - map.floor_z + 2 * tolerance);
      return up >= 0 && down >= 0 && std::fabs(z + up - map.ceiling_z) <= tolerance && std::fabs(z - down - map.floor_z) <= tolerance;
    };
    for (size_t i : order) {
      if (int(out.size()) >= options.max_pocket_positions) break;
      const size_t c = regions[i].best;
      Eigen::Vector3d p = grid.CellCenter(int(c % W), int(c / W), cz);
      p.z() = z;
      if ((regions[i].reached || sealed_room(regions[i], p)) && floor_and_enclosure(p, true)) out.push_back(p);
    }
    return out;
  };
  map.scan_positions = choose_positions(options.scan_spacing_m, true);
  if (map.scan_positions.empty()) map.scan_positions = choose_positions(0.5 * options.scan_spacing_m, true);
  if (map.scan_positions.empty()) {
    map.enclosed = false;
    map.scan_positions = choose_positions(0.5 * options.scan_spacing_m, false);
    if (!map.scan_positions.empty())
      SEMVOX_WARN(scene.source_path << ": the scan does not look like an enclosed interior; free space is computed "
                                       "from positions above the floor without walls around them");
  }
  if (map.scan_positions.empty())
    SEMVOX_WARN(scene.source_path << ": no virtual scan position fits in the scanned space; all non-surface voxels "
                                     "stay unknown");
  map.rays_cast = CastFreeSpace(map.scan_positions, options.max_range_m, &grid, progress);
  // Pockets the grid's positions did not see (only inside an enclosed interior).
  for (int round = 0; round < options.pocket_rounds && map.enclosed && !map.scan_positions.empty(); ++round) {
    const std::vector<Eigen::Vector3d> more = pocket_positions();
    if (more.empty()) break;
    map.rays_cast += CastFreeSpace(more, options.max_range_m, &grid, progress);
    map.scan_positions.insert(map.scan_positions.end(), more.begin(), more.end());
    map.pocket_positions += int(more.size());
  }
  map.seconds_free_space = Seconds(t0);
  return map;
}

}  // namespace semvox
