#include "objects/object_segments.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>

namespace semvox {

bool SegmentOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(floor_band_m >= 0 && ceiling_band_m >= 0)) return fail("floor_band_m and ceiling_band_m must be >= 0");
  if (!(wall_min_run_m > 0 && wall_min_length_m > 0 && wall_max_gap_m >= 0))
    return fail("wall_min_run_m and wall_min_length_m must be > 0, wall_max_gap_m >= 0");
  if (wall_dilation_cells < 0) return fail("wall_dilation_cells must be >= 0");
  if (min_voxels < 1 || max_voxels < min_voxels) return fail("segment sizes: need 1 <= min_voxels <= max_voxels");
  return true;
}

const char* SegmentFeatureName(int f) {
  static const char* kNames[kNumSegmentFeatures] = {"bottom_m",       "top_m",        "length_m",      "width_m",
                                                    "footprint_m2",   "volume_m3",    "fill",          "top_surface_m",
                                                    "top_share",      "up_share",     "side_share",    "wall_distance_m",
                                                    "wall_contact",   "layers",       "under_share",   "ceiling_gap_m"};
  return f >= 0 && f < kNumSegmentFeatures ? kNames[f] : "?";
}

namespace {

// Features of one component (voxels: grid indices).
std::array<float, kNumSegmentFeatures> Describe(const VoxelGrid& grid, const std::vector<uint32_t>& voxels, double floor_z,
                                                double top_z, const std::vector<float>& wall_distance) {
  const auto& d = grid.dims();
  const double res = grid.resolution();
  std::array<float, kNumSegmentFeatures> f{};
  // Footprint cells with their lowest and highest voxel.
  std::map<std::pair<int, int>, std::pair<int, int>> columns;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double zmin = 1e30, zmax = -1e30;
  int up = 0, side = 0;
  std::map<int, int> up_layers;  // z cell -> upward-facing voxels.
  for (uint32_t v : voxels) {
    const auto c = grid.Cell(v);
    const Eigen::Vector3d p = grid.CellCenter(c[0], c[1], c[2]);
    mean += p.head<2>();
    zmin = std::min(zmin, p.z());
    zmax = std::max(zmax, p.z());
    auto [it, inserted] = columns.try_emplace({c[0], c[1]}, c[2], c[2]);
    if (!inserted) it->second = {std::min(it->second.first, c[2]), std::max(it->second.second, c[2])};
    auto occupied = [&](int x, int y, int z) {
      return grid.Contains(x, y, z) && grid.state(grid.Index(x, y, z)) == VoxelState::kOccupied;
    };
    if (!occupied(c[0], c[1], c[2] + 1)) {
      ++up;
      ++up_layers[c[2]];
    }
    if (!occupied(c[0] + 1, c[1], c[2]) || !occupied(c[0] - 1, c[1], c[2]) || !occupied(c[0], c[1] + 1, c[2]) ||
        !occupied(c[0], c[1] - 1, c[2]))
      ++side;
  }
  const double n = double(voxels.size());
  mean /= n;
  // Principal horizontal axes of the footprint.
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& [xy, zz] : columns) {
    const Eigen::Vector2d q = grid.CellCenter(xy.first, xy.second, 0).head<2>() - mean;
    cov += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d major = eig.eigenvectors().col(1), minor = eig.eigenvectors().col(0);
  double a0 = 1e30, a1 = -1e30, b0 = 1e30, b1 = -1e30;
  for (const auto& [xy, zz] : columns) {
    const Eigen::Vector2d q = grid.CellCenter(xy.first, xy.second, 0).head<2>() - mean;
    a0 = std::min(a0, q.dot(major)), a1 = std::max(a1, q.dot(major));
    b0 = std::min(b0, q.dot(minor)), b1 = std::max(b1, q.dot(minor));
  }
  const double length = a1 - a0 + res, width = b1 - b0 + res, height = zmax - zmin + res;
  const double footprint_cells = double(columns.size());
  f[kSegBottom] = float(zmin - floor_z);
  f[kSegTop] = float(zmax - floor_z);
  f[kSegLength] = float(length);
  f[kSegWidth] = float(width);
  f[kSegFootprint] = float(footprint_cells * res * res);
  f[kSegVolume] = float(n * res * res * res);
  f[kSegFill] = float(std::min(1.0, n * res * res * res / (length * width * height)));
  int best_layer = -1, best_count = 0, layers = 0;
  for (const auto& [z, count] : up_layers) {
    if (count > best_count) best_count = count, best_layer = z;
    layers += count >= 0.1 * footprint_cells;
  }
  f[kSegTopSurface] = best_layer >= 0 ? float(grid.CellCenter(0, 0, best_layer).z() - floor_z) : 0.0f;
  f[kSegTopShare] = float(std::min(1.0, best_count / footprint_cells));
  f[kSegUpShare] = float(up / n);
  f[kSegSideShare] = float(side / n);
  // Wall relations from the distance map of wall columns.
  const std::array<int, 3> mc = grid.CellOf(Eigen::Vector3d(mean.x(), mean.y(), zmin));
  const int mx = std::clamp(mc[0], 0, d[0] - 1), my = std::clamp(mc[1], 0, d[1] - 1);
  f[kSegWallDistance] = std::min(3.0f, wall_distance[size_t(my) * d[0] + mx]);
  int contact = 0, under = 0;
  for (const auto& [xy, zz] : columns) {
    contact += wall_distance[size_t(xy.second) * d[0] + xy.first] <= float(2.5 * res);
    under += grid.CellCenter(0, 0, zz.first).z() - floor_z > 0.15;
  }
  f[kSegWallContact] = float(contact / footprint_cells);
  f[kSegLayers] = float(layers);
  f[kSegUnderShare] = float(under / footprint_cells);
  f[kSegCeilingGap] = float(std::max(0.0, top_z - zmax));
  return f;
}

// Two-pass chamfer distance (metres) from every (x, y) cell to the nearest wall column.
std::vector<float> WallDistance(const std::vector<uint8_t>& wall, int w, int h, double res) {
  const float inf = 1e9f, a = float(res), b = float(res * std::sqrt(2.0));
  std::vector<float> dist(wall.size());
  for (size_t i = 0; i < wall.size(); ++i) dist[i] = wall[i] ? 0.0f : inf;
  auto at = [&](int x, int y) -> float& { return dist[size_t(y) * w + x]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float& v = at(x, y);
      if (x > 0) v = std::min(v, at(x - 1, y) + a);
      if (y > 0) v = std::min(v, at(x, y - 1) + a);
      if (x > 0 && y > 0) v = std::min(v, at(x - 1, y - 1) + b);
      if (x + 1 < w && y > 0) v = std::min(v, at(x + 1, y - 1) + b);
    }
  for (int y = h - 1; y >= 0; --y)
    for (int x = w - 1; x >= 0; --x) {
      float& v = at(x, y);
      if (x + 1 < w) v = std::min(v, at(x + 1, y) + a);
      if (y + 1 < h) v = std::min(v, at(x, y + 1) + a);
      if (x + 1 < w && y + 1 < h) v = std::min(v, at(x + 1, y + 1) + b);
      if (x > 0 && y + 1 < h) v = std::min(v, at(x - 1, y + 1) + b);
    }
  return dist;
}

}  // namespace

SegmentationResult SegmentObjects(const VoxelGrid& grid, double floor_z, double ceiling_z, bool ceiling_found,
                                  const SegmentOptions& options) {
  SegmentationResult out;
  const auto& d = grid.dims();
  const double res = grid.resolution();
  out.structure.assign(grid.size(), 0);
  if (grid.size() == 0) return out;
  // Top of the scan: highest occupied layer.
  int top_cell = -1;
  for (size_t i = 0; i < grid.size(); ++i)
    if (grid.state(i) == VoxelState::kOccupied) top_cell = std::max(top_cell, grid.Cell(i)[2]);
  const double top_z = ceiling_found ? ceiling_z : (top_cell >= 0 ? grid.CellCenter(0, 0, top_cell).z() : floor_z);
  // Wall-like columns: a long vertical run of occupied voxels (gaps up to 2 cells bridged).
  const int min_run = std::max(1, int(std::ceil(options.wall_min_run_m / res)));
  std::vector<uint8_t> tall(size_t(d[0]) * d[1], 0);
  for (int y = 0; y < d[1]; ++y)
    for (int x = 0; x < d[0]; ++x) {
      int run_start = -1, last = -100, best = 0;
      for (int z = 0; z < d[2]; ++z) {
        if (grid.state(grid.Index(x, y, z)) != VoxelState::kOccupied) continue;
        if (z - last > 3) run_start = z;
        last = z;
        best = std::max(best, z - run_start + 1);
      }
      tall[size_t(y) * d[0] + x] = best >= min_run;
    }
  // Walls: wall-like columns lined up along x or y over wall_min_length_m.
  std::vector<uint8_t> wall(size_t(d[0]) * d[1], 0);
  const int min_len = std::max(1, int(std::ceil(options.wall_min_length_m / res)));
  const int max_gap = int(std::floor(options.wall_max_gap_m / res));
  for (int axis = 0; axis < 2; ++axis) {
    const int lines = axis == 0 ? d[1] : d[0], along = axis == 0 ? d[0] : d[1];
    for (int l = 0; l < lines; ++l) {
      auto idx = [&](int t) { return axis == 0 ? size_t(l) * d[0] + t : size_t(t) * d[0] + l; };
      int t = 0;
      while (t < along) {
        if (!tall[idx(t)]) {
          ++t;
          continue;
        }
        int end = t, gap = 0;
        for (int u = t + 1; u < along && gap <= max_gap; ++u) {
          if (tall[idx(u)]) end = u, gap = 0;
          else ++gap;
        }
        if (end - t + 1 >= min_len)
          for (int u = t; u <= end; ++u)
            if (tall[idx(u)]) wall[idx(u)] = 1;
        t = end + 1;
      }
    }
  }
  if (options.wall_dilation_cells > 0) {
    std::vector<uint8_t> grown = wall;
    const int r = options.wall_dilation_cells;
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        if (!wall[size_t(y) * d[0] + x]) continue;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx >= 0 && yy >= 0 && xx < d[0] && yy < d[1]) grown[size_t(yy) * d[0] + xx] = 1;
          }
      }
    wall.swap(grown);
  }
  const std::vector<float> wall_distance = WallDistance(wall, d[0], d[1], res);
  for (size_t i = 0; i < grid.size(); ++i) {
    if (grid.state(i) != VoxelState::kOccupied) continue;
    const auto c = grid.Cell(i);
    const double z = grid.CellCenter(c[0], c[1], c[2]).z();
    if (z < floor_z + options.floor_band_m) out.structure[i] = 1;
    else if (ceiling_found && z > ceiling_z - options.ceiling_band_m) out.structure[i] = 2;
    else if (wall[size_t(c[1]) * d[0] + c[0]]) out.structure[i] = 3;
  }
  // 26-connected components of the rest.
  std::vector<uint8_t> seen(grid.size(), 0);
  std::vector<uint32_t> stack, comp;
  for (size_t s = 0; s < grid.size(); ++s) {
    if (seen[s] || grid.state(s) != VoxelState::kOccupied || out.structure[s]) continue;
    comp.clear();
    seen[s] = 1;
    stack.push_back(uint32_t(s));
    while (!stack.empty()) {
      const uint32_t i = stack.back();
      stack.pop_back();
      comp.push_back(i);
      const auto c = grid.Cell(i);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
            if (!grid.Contains(x, y, z)) continue;
            const size_t j = grid.Index(x, y, z);
            if (seen[j] || grid.state(j) != VoxelState::kOccupied || out.structure[j]) continue;
            seen[j] = 1;
            stack.push_back(uint32_t(j));
          }
    }
    if (int(comp.size()) < options.min_voxels || int(comp.size()) > options.max_voxels) continue;
    std::sort(comp.begin(), comp.end());
    ObjectSegment seg;
    seg.voxels = comp;
    seg.features = Describe(grid, comp, floor_z, top_z, wall_distance);
    out.segments.push_back(std::move(seg));
  }
  return out;
}

}  // namespace semvox
