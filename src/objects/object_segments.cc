#include "objects/object_segments.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "core/voxel_key.h"

namespace semvox {

bool SegmentOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(floor_band_m >= 0 && ceiling_band_m >= 0)) return fail("floor_band_m and ceiling_band_m must be >= 0");
  if (!(wall_min_coverage > 0 && wall_min_coverage <= 1)) return fail("wall_min_coverage must be in (0, 1]");
  if (!(wall_band_bottom_m >= 0 && wall_band_top_m >= 0 && wall_min_length_m > 0))
    return fail("wall_band_bottom_m and wall_band_top_m must be >= 0, wall_min_length_m > 0");
  if (wall_dilation_cells < 0) return fail("wall_dilation_cells must be >= 0");
  if (!(split_height_m >= 0 && split_top_step_m >= 0 && min_part_area_m2 >= 0 && rise_min_thickness_m >= 0))
    return fail("split_height_m, split_top_step_m, min_part_area_m2 and rise_min_thickness_m must be >= 0");
  if (min_voxels < 1 || max_voxels < min_voxels) return fail("segment sizes: need 1 <= min_voxels <= max_voxels");
  if (!(front_min_depth_m >= 0 && (front_max_depth_m == 0 || front_max_depth_m > front_min_depth_m)))
    return fail("front_min_depth_m must be >= 0 and front_max_depth_m 0 or > front_min_depth_m");
  if (!(front_free_share > 0 && front_free_share <= 1)) return fail("front_free_share must be in (0, 1]");
  return true;
}

const char* SegmentFeatureName(int f) {
  static const char* kNames[kNumSegmentFeatures] = {"bottom_m",       "top_m",        "length_m",      "width_m",
                                                    "footprint_m2",   "volume_m3",    "fill",          "top_surface_m",
                                                    "top_share",      "up_share",     "side_share",    "wall_distance_m",
                                                    "wall_contact",   "layers",       "under_share",   "ceiling_gap_m",
                                                    "thickness_m",    "neighbour_rise_m"};
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
  // Thickness: breadth-first chessboard distance from the footprint's edge inwards.
  std::map<std::pair<int, int>, int> depth;
  std::vector<std::pair<int, int>> queue;
  for (const auto& [xy, zz] : columns) {
    bool edge = false;
    for (int dy = -1; dy <= 1 && !edge; ++dy)
      for (int dx = -1; dx <= 1 && !edge; ++dx) edge = !columns.count({xy.first + dx, xy.second + dy});
    if (edge) depth[xy] = 1, queue.push_back(xy);
  }
  int deepest = 1;
  for (size_t head = 0; head < queue.size(); ++head) {
    const auto q = queue[head];
    const int dq = depth.at(q);
    deepest = std::max(deepest, dq);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::pair<int, int> n{q.first + dx, q.second + dy};
        if (columns.count(n) && !depth.count(n)) depth[n] = dq + 1, queue.push_back(n);
      }
  }
  f[kSegThickness] = float(std::min(length, std::min(width, (2.0 * deepest - 1.0) * res)));
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

// Cuts one component into parts of similar top height: every footprint column (x, y) gets the height of
// its highest voxel; 8-connected columns whose tops are within `step` cells of the region's mean top grow
// into one region;
// regions under `min_cells` columns join the neighbouring region they share most border with (largest
// first, repeated until none is left or nothing touches). Each voxel goes to its column's region. Objects
// that touch (a desk beside a bed, a table against a sofa) have different tops and come apart; a flat
// top with noise, a sloped cushion and the pillows on a bed stay one.
std::vector<std::vector<uint32_t>> SplitByTopHeight(const VoxelGrid& grid, std::vector<uint32_t> voxels, int step, int min_cells) {
  std::map<std::pair<int, int>, int> top;  // column -> highest cell
  for (uint32_t v : voxels) {
    const auto c = grid.Cell(v);
    auto [it, inserted] = top.try_emplace({c[0], c[1]}, c[2]);
    if (!inserted) it->second = std::max(it->second, c[2]);
  }
  if (step <= 0 || top.size() < 2) return {std::move(voxels)};
  std::map<std::pair<int, int>, int> region;
  std::vector<int> size;
  for (const auto& [xy, z] : top) {
    if (region.count(xy)) continue;
    const int id = int(size.size());
    size.push_back(0);
    // Breadth first, against the region's mean top so far: a chain of small steps (a sloped cushion
    // between a seat and a back) does not join surfaces of different heights.
    std::vector<std::pair<int, int>> queue{xy};
    region[xy] = id;
    double sum = 0;
    for (size_t head = 0; head < queue.size(); ++head) {
      const auto q = queue[head];
      ++size.back();
      sum += top.at(q);
      const double mean = sum / size.back();
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::pair<int, int> n{q.first + dx, q.second + dy};
          const auto t = top.find(n);
          if (t == top.end() || region.count(n) || std::abs(t->second - mean) > step + 0.5) continue;
          region[n] = id;
          queue.push_back(n);
        }
    }
  }
  // Merge small regions into the neighbour with the longest shared border.
  std::vector<int> parent(size.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = int(i);
  auto find = [&](int a) {
    while (parent[size_t(a)] != a) a = parent[size_t(a)] = parent[size_t(parent[size_t(a)])];
    return a;
  };
  for (bool changed = true; changed;) {
    changed = false;
    std::map<std::pair<int, int>, int> border;  // (small region, neighbour) -> shared column pairs
    for (const auto& [xy, r0] : region) {
      const int a = find(r0);
      if (size[size_t(a)] >= min_cells) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = region.find({xy.first + dx, xy.second + dy});
          if (it == region.end()) continue;
          const int b = find(it->second);
          if (b != a) ++border[{a, b}];
        }
    }
    std::map<int, std::pair<int, int>> best;  // small region -> (border, neighbour)
    for (const auto& [ab, n] : border) {
      auto& cur = best[ab.first];
      if (n > cur.first || (n == cur.first && size[size_t(ab.second)] > size[size_t(cur.second)])) cur = {n, ab.second};
    }
    for (const auto& [a, nb] : best) {
      const int ra = find(a), rb = find(nb.second);
      if (ra == rb || size[size_t(ra)] >= min_cells) continue;
      parent[size_t(ra)] = rb;
      size[size_t(rb)] += size[size_t(ra)];
      changed = true;
    }
  }
  std::map<int, std::vector<uint32_t>> parts;
  for (uint32_t v : voxels) {
    const auto c = grid.Cell(v);
    parts[find(region.at({c[0], c[1]}))].push_back(v);
  }
  std::vector<std::vector<uint32_t>> out;
  for (auto& [r, part] : parts) out.push_back(std::move(part));
  return out;
}

}  // namespace

namespace {

// SegmentObjects on `grid` itself.
SegmentationResult SegmentObjectsOnGrid(const VoxelGrid& grid, double floor_z, double ceiling_z, bool ceiling_found,
                                        const SegmentOptions& options) {
  SegmentationResult out;
  const auto& d = grid.dims();
  const double res = grid.resolution();
  out.structure.assign(grid.size(), 0);
  if (grid.size() == 0) return out;
  const int top_cell = grid.TopOccupiedLayer();  // Top of the scan.
  const double top_z = ceiling_found ? ceiling_z : (top_cell >= 0 ? grid.CellCenter(0, 0, top_cell).z() : floor_z);
  // Wall columns: occupied over at least wall_min_coverage of the band [floor + wall_band_bottom_m, top -
  // wall_band_top_m] (gaps of any length allowed: a sparse scan leaves holes, windows and doors cut walls),
  // in 8-connected groups that extend over at least wall_min_length_m (so walls need not be axis-aligned:
  // a diagonal bathroom wall is a wall; a lone tall column is not).
  const int band_lo = std::max(0, grid.CellOf(Eigen::Vector3d(0, 0, floor_z + options.wall_band_bottom_m))[2]);
  const int band_hi = std::min(d[2] - 1, grid.CellOf(Eigen::Vector3d(0, 0, top_z - options.wall_band_top_m))[2]);
  const int band_cells = band_hi - band_lo + 1;
  std::vector<uint8_t> wall(size_t(d[0]) * d[1], 0);
  if (band_cells >= 2) {
    std::vector<uint8_t> free_column(wall.size(), 0);
    std::vector<int> column_top(wall.size(), -1);
    int top_below_ceiling = d[2] - 1;
    if (ceiling_found) {
      const Eigen::Vector3d lo = grid.MinCorner();
      const int z = int(std::floor((ceiling_z - options.ceiling_band_m - lo.z()) / res - 0.5));  // Centres not in the ceiling band.
      top_below_ceiling = std::clamp(z, 0, d[2] - 1);
    }
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        int count = 0, free = 0;
        for (int z = band_lo; z <= band_hi; ++z) {
          const VoxelState st = grid.state(grid.Index(x, y, z));
          count += st == VoxelState::kOccupied;
          free += st == VoxelState::kFree;
        }
        const size_t i = size_t(y) * d[0] + x;
        wall[i] = count >= options.wall_min_coverage * band_cells;
        free_column[i] = free >= options.front_free_share * band_cells;
        // The column's top below the ceiling: the ceiling spans every room, so a column that reached it would
        // "rise" above a door leaf and its lintel wherever the room behind the door was not seen free, and
        // the door became a furniture front depending on where the scan positions fell.
        for (int z = top_below_ceiling; z >= 0; --z)
          if (grid.state(grid.Index(x, y, z)) == VoxelState::kOccupied) {
            column_top[i] = z;
            break;
          }
      }
    if (options.front_max_depth_m > 0) {
      // Furniture fronts (see SegmentOptions): free in front, unseen behind up to a higher occupied column.
      const int k_min = std::max(1, int(std::ceil(options.front_min_depth_m / res - 1e-9)));
      const int k_max = int(std::floor(options.front_max_depth_m / res + 1e-9));
      const int rise = std::max(1, int(std::lround(0.2 / res)));
      std::vector<uint8_t> front(wall.size(), 0);
      const int dir[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      // Whether column (x, y) is free over at least front_free_share of the wall band up to cell `top`.
      const auto free_below = [&](int x, int y, int top) {
        const int hi = std::min(band_hi, top);
        if (hi < band_lo) return bool(free_column[size_t(y) * d[0] + x]);
        int free = 0;
        for (int z = band_lo; z <= hi; ++z) free += grid.state(grid.Index(x, y, z)) == VoxelState::kFree;
        return free >= options.front_free_share * (hi - band_lo + 1);
      };
      for (int y = 0; y < d[1]; ++y)
        for (int x = 0; x < d[0]; ++x) {
          const size_t i = size_t(y) * d[0] + x;
          if (!wall[i]) continue;
          for (const auto& u : dir) {
            const int fx = x - u[0], fy = y - u[1];
            if (fx < 0 || fy < 0 || fx >= d[0] || fy >= d[1] || !free_column[size_t(fy) * d[0] + fx]) continue;
            bool hit = false;
            for (int k = 1; k <= k_max; ++k) {
              const int bx = x + k * u[0], by = y + k * u[1];
              if (bx < 0 || by < 0 || bx >= d[0] || by >= d[1]) break;
              const size_t j = size_t(by) * d[0] + bx;
              // Room, not the inside: free below the front's top. Above a cabinet or fridge the scan sees
              // free space over the top, which says nothing about its inside.
              if (free_below(bx, by, column_top[i])) break;
              const bool higher = column_top[j] >= column_top[i] + rise;
              if (k >= k_min && higher) {
                hit = true;
                break;
              }
              if (wall[j] && k < k_min) break;  // The wall's own thickness, or along a wall.
            }
            if (hit) {
              front[i] = 1;
              break;
            }
          }
        }
      // The object's sides (and the rest of its face) join the front: wall columns 8-connected to a front,
      // no higher than its top + 0.1 m and within front_max_depth_m of it. The wall beside or behind it rises
      // higher and stays wall.
      struct Grow {
        int i, top, steps;
      };
      std::vector<Grow> queue;
      for (size_t i = 0; i < wall.size(); ++i)
        if (front[i]) queue.push_back({int(i), column_top[i], 0});
      const int slack = std::max(1, int(std::lround(0.1 / res)));
      for (size_t head = 0; head < queue.size(); ++head) {
        const Grow g = queue[head];
        if (g.steps >= k_max) continue;
        const int x = g.i % d[0], y = g.i / d[0];
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= d[0] || yy >= d[1]) continue;
            const size_t j = size_t(yy) * d[0] + xx;
            if (!wall[j] || front[j] || column_top[j] > g.top + slack) continue;
            front[j] = 1;
            queue.push_back({int(j), g.top, g.steps + 1});
          }
      }
      for (size_t i = 0; i < wall.size(); ++i)
        if (front[i]) wall[i] = 0;
    }
    std::vector<uint8_t> done(wall.size(), 0);
    std::vector<int> stack, group;
    for (size_t s = 0; s < wall.size(); ++s) {
      if (!wall[s] || done[s]) continue;
      group.clear();
      stack.assign(1, int(s));
      done[s] = 1;
      int x0 = d[0], x1 = -1, y0 = d[1], y1 = -1;
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        group.push_back(i);
        const int x = i % d[0], y = i / d[0];
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= d[0] || yy >= d[1]) continue;
            const size_t j = size_t(yy) * d[0] + xx;
            if (wall[j] && !done[j]) done[j] = 1, stack.push_back(int(j));
          }
      }
      const double extent = res * std::hypot(double(x1 - x0 + 1), double(y1 - y0 + 1));
      if (extent < options.wall_min_length_m)
        for (int i : group) wall[size_t(i)] = 0;
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
  out.wall_distance = WallDistance(wall, d[0], d[1], res);
  out.floor_z = floor_z;
  out.top_z = top_z;
  const std::vector<float>& wall_distance = out.wall_distance;
  for (size_t i = 0; i < grid.size(); ++i) {
    if (grid.state(i) != VoxelState::kOccupied) continue;
    const auto c = grid.Cell(i);
    const double z = grid.CellCenter(c[0], c[1], c[2]).z();
    if (z < floor_z + options.floor_band_m) out.structure[i] = 1;
    else if (ceiling_found && z > ceiling_z - options.ceiling_band_m) out.structure[i] = 2;
    else if (wall[size_t(c[1]) * d[0] + c[0]]) out.structure[i] = 3;
  }
  // 26-connected components of the rest, in two passes so that low clutter, rugs and scan noise on the
  // floor do not bridge a room's furniture into one segment: components of the voxels at least
  // `split_height_m` above the floor first (the cores), then the lower voxels join the core they touch
  // (breadth first from all cores at once, ties to the core found first), and the low voxels that reach
  // no core form components of their own.
  const int split_cell = grid.CellOf(Eigen::Vector3d(0, 0, floor_z + options.split_height_m))[2];
  std::vector<int32_t> component(grid.size(), -1);
  auto is_object = [&](size_t i) { return grid.state(i) == VoxelState::kOccupied && !out.structure[i]; };
  auto for_neighbours = [&](uint32_t i, auto&& visit) {
    const auto c = grid.Cell(i);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
          if (grid.Contains(x, y, z)) visit(uint32_t(grid.Index(x, y, z)));
        }
  };
  int num_components = 0;
  std::vector<uint32_t> stack;
  auto flood = [&](size_t seed, bool high_only) {
    const int id = num_components++;
    component[seed] = id;
    stack.assign(1, uint32_t(seed));
    while (!stack.empty()) {
      const uint32_t i = stack.back();
      stack.pop_back();
      for_neighbours(i, [&](uint32_t j) {
        if (component[j] >= 0 || !is_object(j) || (high_only && grid.Cell(j)[2] < split_cell)) return;
        component[j] = id;
        stack.push_back(j);
      });
    }
  };
  for (size_t s = 0; s < grid.size(); ++s)
    if (component[s] < 0 && is_object(s) && grid.Cell(s)[2] >= split_cell) flood(s, true);
  std::vector<uint32_t> frontier;
  for (size_t s = 0; s < grid.size(); ++s)
    if (component[s] >= 0) frontier.push_back(uint32_t(s));
  while (!frontier.empty()) {
    std::vector<uint32_t> next;
    for (uint32_t i : frontier)
      for_neighbours(i, [&](uint32_t j) {
        if (component[j] >= 0 || !is_object(j)) return;
        component[j] = component[i];
        next.push_back(j);
      });
    frontier.swap(next);
  }
  for (size_t s = 0; s < grid.size(); ++s)
    if (component[s] < 0 && is_object(s)) flood(s, false);
  std::vector<std::vector<uint32_t>> whole(static_cast<size_t>(num_components));
  for (size_t i = 0; i < grid.size(); ++i)
    if (component[i] >= 0) whole[size_t(component[i])].push_back(uint32_t(i));
  const int step = int(std::lround(options.split_top_step_m / res));
  const int min_cells = std::max(1, int(std::lround(options.min_part_area_m2 / (res * res))));
  struct Part {
    std::vector<uint32_t> voxels;
    std::array<float, kNumSegmentFeatures> features{};
  };
  std::vector<Part> parts;
  for (std::vector<uint32_t>& comp : whole) {
    std::vector<std::vector<uint32_t>> cut = SplitByTopHeight(grid, std::move(comp), step, min_cells);
    // Tops of the parts, and which part owns each column, for the rise of the highest adjacent part.
    std::map<std::pair<int, int>, int> owner;
    std::vector<int> top(cut.size(), -1);
    for (size_t p = 0; p < cut.size(); ++p)
      for (uint32_t v : cut[p]) {
        const auto c = grid.Cell(v);
        owner[{c[0], c[1]}] = int(p);
        top[p] = std::max(top[p], c[2]);
      }
    std::vector<std::array<float, kNumSegmentFeatures>> features(cut.size());
    for (size_t p = 0; p < cut.size(); ++p) {
      std::sort(cut[p].begin(), cut[p].end());
      features[p] = Describe(grid, cut[p], floor_z, top_z, wall_distance);
    }
    std::vector<int> highest_neighbour(cut.size(), -1);
    for (const auto& [xy, p] : owner)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = owner.find({xy.first + dx, xy.second + dy});
          if (it == owner.end() || it->second == p) continue;
          if (features[size_t(it->second)][kSegThickness] < options.rise_min_thickness_m) continue;
          highest_neighbour[size_t(p)] = std::max(highest_neighbour[size_t(p)], top[size_t(it->second)]);
        }
    for (size_t p = 0; p < cut.size(); ++p) {
      Part part;
      part.voxels = std::move(cut[p]);
      part.features = features[p];
      part.features[kSegNeighbourRise] = highest_neighbour[p] > top[p] ? float((highest_neighbour[p] - top[p]) * res) : 0.f;
      parts.push_back(std::move(part));
    }
  }
  std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) { return a.voxels.front() < b.voxels.front(); });
  for (Part& part : parts) {
    if (int(part.voxels.size()) < options.min_voxels || int(part.voxels.size()) > options.max_voxels) continue;
    ObjectSegment seg;
    seg.features = part.features;
    seg.voxels = std::move(part.voxels);
    out.segments.push_back(std::move(seg));
  }
  return out;
}

// The lattice of kSegmentCellM cells holding `grid`'s voxel centres, on OctoMap keys: a cell is occupied when any voxel
// in it is, else free when any is, else unknown. `cell_of[axis][i]` is the lattice cell of the grid's cell i on
// that axis (centres map to cells axis by axis).
VoxelGrid FeatureLattice(const VoxelGrid& grid, std::array<std::vector<int>, 3>* cell_of) {
  const double step = kSegmentCellM;
  const auto& d = grid.dims();
  std::array<int, 3> origin{}, dims{};
  for (int a = 0; a < 3; ++a) {
    const auto key = [&](int i) { return int(CoordToKeyIndex(KeyIndexToCoord(grid.origin_key()[a] + i, grid.resolution()), step)); };
    origin[a] = key(0);
    dims[a] = key(d[a] - 1) - origin[a] + 1;
    (*cell_of)[a].resize(size_t(d[a]));
    for (int i = 0; i < d[a]; ++i) (*cell_of)[a][size_t(i)] = key(i) - origin[a];
  }
  VoxelGrid lattice(step, origin, dims);
  for (size_t i = 0; i < grid.size(); ++i) {
    const VoxelState s = grid.state(i);
    if (s == VoxelState::kUnknown) continue;
    const auto c = grid.Cell(i);
    const size_t j = lattice.Index((*cell_of)[0][size_t(c[0])], (*cell_of)[1][size_t(c[1])], (*cell_of)[2][size_t(c[2])]);
    if (s == VoxelState::kOccupied || lattice.state(j) == VoxelState::kUnknown) lattice.set_state(j, s);
  }
  return lattice;
}

}  // namespace

SegmentationResult SegmentObjects(const VoxelGrid& grid, double floor_z, double ceiling_z, bool ceiling_found,
                                  const SegmentOptions& options) {
  if (grid.size() == 0 || grid.resolution() >= kSegmentCellM * (1 - 1e-9))
    return SegmentObjectsOnGrid(grid, floor_z, ceiling_z, ceiling_found, options);
  // A finer map: segments are found and described on the lattice, and each voxel takes its lattice cell's part.
  std::array<std::vector<int>, 3> cell_of;
  auto lattice = std::make_shared<VoxelGrid>(FeatureLattice(grid, &cell_of));
  SegmentationResult coarse = SegmentObjectsOnGrid(*lattice, floor_z, ceiling_z, ceiling_found, options);
  const auto& d = grid.dims();
  const auto& ld = lattice->dims();
  const auto parent = [&](const std::array<int, 3>& c) {
    return lattice->Index(cell_of[0][size_t(c[0])], cell_of[1][size_t(c[1])], cell_of[2][size_t(c[2])]);
  };
  SegmentationResult out;
  out.floor_z = coarse.floor_z;
  out.top_z = coarse.top_z;
  out.structure.assign(grid.size(), 0);
  out.wall_distance.resize(size_t(d[0]) * size_t(d[1]));
  for (int y = 0; y < d[1]; ++y)
    for (int x = 0; x < d[0]; ++x)
      out.wall_distance[size_t(y) * size_t(d[0]) + size_t(x)] =
          coarse.wall_distance[size_t(cell_of[1][size_t(y)]) * size_t(ld[0]) + size_t(cell_of[0][size_t(x)])];
  std::vector<int32_t> segment_of(lattice->size(), -1);
  for (size_t s = 0; s < coarse.segments.size(); ++s)
    for (uint32_t v : coarse.segments[s].voxels) segment_of[v] = int32_t(s);
  out.segments.resize(coarse.segments.size());
  for (size_t s = 0; s < coarse.segments.size(); ++s) out.segments[s].features = coarse.segments[s].features;
  for (size_t i = 0; i < grid.size(); ++i) {
    if (grid.state(i) != VoxelState::kOccupied) continue;
    const size_t j = parent(grid.Cell(i));
    out.structure[i] = coarse.structure[j];
    if (segment_of[j] >= 0) out.segments[size_t(segment_of[j])].voxels.push_back(uint32_t(i));
  }
  out.feature_grid = std::move(lattice);
  out.feature_wall_distance = std::move(coarse.wall_distance);
  return out;
}

std::array<float, kNumSegmentFeatures> DescribeVoxels(const VoxelGrid& grid, const std::vector<uint32_t>& voxels,
                                                      const SegmentationResult& seg) {
  if (voxels.empty() || seg.wall_distance.size() != size_t(grid.dims()[0]) * size_t(grid.dims()[1])) return {};
  if (!seg.feature_grid) return Describe(grid, voxels, seg.floor_z, seg.top_z, seg.wall_distance);
  // Measured on the lattice the segments were described on: the cells holding the voxels.
  const VoxelGrid& lattice = *seg.feature_grid;
  std::vector<uint32_t> cells;
  cells.reserve(voxels.size());
  for (uint32_t v : voxels) {
    const auto c = grid.Cell(v);
    const auto l = lattice.CellOf(grid.CellCenter(c[0], c[1], c[2]));
    if (lattice.Contains(l[0], l[1], l[2])) cells.push_back(uint32_t(lattice.Index(l[0], l[1], l[2])));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  if (cells.empty()) return {};
  return Describe(lattice, cells, seg.floor_z, seg.top_z, seg.feature_wall_distance);
}

}  // namespace semvox
