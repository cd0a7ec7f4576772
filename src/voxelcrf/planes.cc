#include "voxelcrf/planes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

namespace semvox {

bool PlaneDetectionOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(offset_tolerance_voxels > 0))
    return fail("offset_tolerance_voxels = " + std::to_string(offset_tolerance_voxels) + ". Violated constraint: > 0");
  if (max_planes < 0) return fail("max_planes = " + std::to_string(max_planes) + ". Violated constraint: >= 0");
  if (gap_cells < 0) return fail("gap_cells = " + std::to_string(gap_cells) + ". Violated constraint: >= 0");
  return true;
}

std::vector<Eigen::Vector2d> ConvexHull2D(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

namespace {

bool InsideConvex(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& q) {
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % hull.size()];
    if ((b.x() - a.x()) * (q.y() - a.y()) - (b.y() - a.y()) * (q.x() - a.x()) < -1e-9) return false;
  }
  return true;
}

double PolygonArea(const std::vector<Eigen::Vector2d>& h) {
  double a = 0;
  for (size_t i = 0; i < h.size(); ++i) {
    const auto& p = h[i];
    const auto& q = h[(i + 1) % h.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * std::abs(a);
}

// Splits `members` (nodes with 2D cells) into 8-connected pieces after closing gaps of `gap` cells.
std::vector<std::vector<int>> ConnectedPieces(const std::vector<int>& members, const std::vector<Eigen::Vector2i>& cells, int gap) {
  Eigen::Vector2i lo = cells[0], hi = cells[0];
  for (const auto& c : cells) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  lo.array() -= gap;
  hi.array() += gap;
  const int w = hi.x() - lo.x() + 1, h = hi.y() - lo.y() + 1;
  std::vector<uint8_t> mask(size_t(w) * h, 0);
  for (const auto& c : cells)
    for (int dy = -gap; dy <= gap; ++dy)
      for (int dx = -gap; dx <= gap; ++dx) mask[size_t(c.y() - lo.y() + dy) * w + (c.x() - lo.x() + dx)] = 1;
  std::vector<int> comp(mask.size(), -1);
  int n = 0;
  std::vector<int> stack;
  for (size_t s = 0; s < mask.size(); ++s) {
    if (!mask[s] || comp[s] >= 0) continue;
    comp[s] = n;
    stack.push_back(int(s));
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      const int x = i % w, y = i / w;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
          const size_t j = size_t(yy) * w + xx;
          if (mask[j] && comp[j] < 0) comp[j] = n, stack.push_back(int(j));
        }
    }
    ++n;
  }
  std::vector<std::vector<int>> pieces(static_cast<size_t>(n));
  for (size_t k = 0; k < members.size(); ++k)
    pieces[size_t(comp[size_t(cells[k].y() - lo.y()) * w + (cells[k].x() - lo.x())])].push_back(members[k]);
  return pieces;
}

}  // namespace

std::vector<DetectedPlane> DetectPlanes(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev,
                                        const PlaneDetectionOptions& options) {
  const double res = grid.resolution();
  std::vector<int> cand;
  std::vector<Eigen::Vector3f> pos;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes.initial_state[i] != uint8_t(VoxelState::kOccupied) || ev.hits[i] == 0 || ev.normal[i].squaredNorm() < 0.25f) continue;
    cand.push_back(int(i));
    const auto c = grid.Cell(nodes.voxel[i]);
    pos.push_back(grid.CellCenter(c[0], c[1], c[2]).cast<float>());
  }
  const float cos_tol = float(std::cos(options.normal_angle_deg * M_PI / 180.0));
  std::vector<uint8_t> used(cand.size(), 0);
  std::vector<DetectedPlane> planes;
  // Dominant normal directions, one at a time.
  for (int round = 0; round < 64; ++round) {
    std::unordered_map<int, std::pair<int, Eigen::Vector3f>> hist;
    constexpr float kQ = 6.0f;
    for (size_t k = 0; k < cand.size(); ++k) {
      if (used[k]) continue;
      const Eigen::Vector3f& n = ev.normal[size_t(cand[k])];
      const int key = (int(std::lround(n.x() * kQ)) + 8) * 289 + (int(std::lround(n.y() * kQ)) + 8) * 17 + (int(std::lround(n.z() * kQ)) + 8);
      auto& e = hist[key];
      if (e.first == 0) e.second.setZero();
      ++e.first;
      e.second += n;
    }
    int best = -1, best_count = 0;
    for (const auto& [key, e] : hist)
      if (e.first > best_count || (e.first == best_count && key < best)) best = key, best_count = e.first;
    if (best_count < options.min_voxels) break;
    Eigen::Vector3f dir = hist[best].second.normalized();
    std::vector<size_t> group;
    for (int refine = 0; refine < 3; ++refine) {
      group.clear();
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (size_t k = 0; k < cand.size(); ++k)
        if (!used[k] && ev.normal[size_t(cand[k])].dot(dir) >= cos_tol) group.push_back(k), sum += ev.normal[size_t(cand[k])];
      if (group.empty()) break;
      dir = sum.normalized();
    }
    if (int(group.size()) < options.min_voxels) {
      // Not enough support around the mode after refinement: retire the mode's voxels and go on.
      for (size_t k = 0; k < cand.size(); ++k)
        if (!used[k] && ev.normal[size_t(cand[k])].dot(dir) >= cos_tol) used[k] = 1;
      if (group.empty()) break;
      continue;
    }
    for (size_t k : group) used[k] = 1;
    // Offsets along dir, half-voxel bins.
    const double bin = 0.5 * res, tol = options.offset_tolerance_voxels * res;
    std::vector<double> off(group.size());
    std::map<int64_t, int> offset_hist;
    for (size_t g = 0; g < group.size(); ++g) {
      off[g] = double(dir.dot(pos[group[g]]));
      ++offset_hist[int64_t(std::floor(off[g] / bin))];
    }
    std::vector<uint8_t> taken(group.size(), 0);
    while (true) {
      int64_t peak = 0;
      int peak_votes = 0;
      for (const auto& [b, c] : offset_hist) {
        int votes = c;
        if (auto it = offset_hist.find(b - 1); it != offset_hist.end()) votes += it->second;
        if (auto it = offset_hist.find(b + 1); it != offset_hist.end()) votes += it->second;
        if (votes > peak_votes) peak_votes = votes, peak = b;
      }
      if (peak_votes < options.min_voxels) break;
      double d0 = (double(peak) + 0.5) * bin;
      for (int refine = 0; refine < 2; ++refine) {
        double s = 0;
        int c = 0;
        for (size_t g = 0; g < group.size(); ++g)
          if (!taken[g] && std::abs(off[g] - d0) <= tol) s += off[g], ++c;
        if (c) d0 = s / c;
      }
      std::vector<int> inliers;
      std::vector<Eigen::Vector2i> cells;
      const Eigen::Vector3f u = dir.cross(std::abs(dir.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX()).normalized();
      const Eigen::Vector3f v = dir.cross(u);
      for (size_t g = 0; g < group.size(); ++g) {
        if (taken[g] || std::abs(off[g] - d0) > tol) continue;
        taken[g] = 1;
        auto it = offset_hist.find(int64_t(std::floor(off[g] / bin)));
        if (--it->second == 0) offset_hist.erase(it);
        inliers.push_back(cand[group[g]]);
        const Eigen::Vector3f& p = pos[group[g]];
        cells.emplace_back(int(std::floor(u.dot(p) / res)), int(std::floor(v.dot(p) / res)));
      }
      if (inliers.empty()) break;
      for (auto& piece : ConnectedPieces(inliers, cells, options.gap_cells)) {
        if (int(piece.size()) < options.min_voxels) continue;
        DetectedPlane plane;
        plane.normal = dir;
        plane.offset = float(d0);
        plane.members = piece;
        std::vector<Eigen::Vector2d> pts;
        for (int node : piece) {
          const auto c = grid.Cell(nodes.voxel[size_t(node)]);
          const Eigen::Vector3f p = grid.CellCenter(c[0], c[1], c[2]).cast<float>();
          const double pu = u.dot(p), pv = v.dot(p);
          for (int cu = -1; cu <= 1; cu += 2)
            for (int cv = -1; cv <= 1; cv += 2) pts.emplace_back(pu + 0.5 * cu * res, pv + 0.5 * cv * res);
        }
        const std::vector<Eigen::Vector2d> hull = ConvexHull2D(std::move(pts));
        plane.area_m2 = PolygonArea(hull);
        Eigen::Vector2d lo = hull[0], hi = hull[0];
        for (const auto& q : hull) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
        const double step = 0.5 * res;
        std::vector<int> in;
        for (double a = lo.x() + 0.25 * res; a < hi.x(); a += step)
          for (double b = lo.y() + 0.25 * res; b < hi.y(); b += step) {
            if (!InsideConvex(hull, {a, b})) continue;
            const Eigen::Vector3d q = (double(d0) * dir + float(a) * u + float(b) * v).cast<double>();
            const auto cell = grid.CellOf(q);
            if (!grid.Contains(cell[0], cell[1], cell[2])) continue;
            const int32_t node = nodes.node_of_voxel[grid.Index(cell[0], cell[1], cell[2])];
            if (node >= 0 && nodes.initial_state[size_t(node)] != uint8_t(VoxelState::kFree)) in.push_back(node);
          }
        in.insert(in.end(), piece.begin(), piece.end());
        std::sort(in.begin(), in.end());
        in.erase(std::unique(in.begin(), in.end()), in.end());
        plane.hull_nodes = std::move(in);
        planes.push_back(std::move(plane));
      }
    }
  }
  std::stable_sort(planes.begin(), planes.end(), [](const DetectedPlane& a, const DetectedPlane& b) { return a.members.size() > b.members.size(); });
  if (int(planes.size()) > options.max_planes) planes.resize(size_t(options.max_planes));
  return planes;
}

}  // namespace semvox
