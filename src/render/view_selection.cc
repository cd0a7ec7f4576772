#include "render/view_selection.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <queue>
#include <sstream>

namespace semvox {

bool ViewSelectionOptions::Check(std::string* error) const { return CheckOptions(*this, Options(), error); }

std::vector<uint32_t> SurfaceVoxels(const VoxelGrid& grid) {
  std::vector<uint32_t> surface;
  const auto& d = grid.dims();
  const int offsets[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const size_t i = grid.Index(x, y, z);
        if (grid.state(i) != VoxelState::kOccupied) continue;
        for (const auto& o : offsets) {
          const int a = x + o[0], b = y + o[1], c = z + o[2];
          if (grid.Contains(a, b, c) && grid.state(grid.Index(a, b, c)) == VoxelState::kFree) {
            surface.push_back(uint32_t(i));
            break;
          }
        }
      }
  return surface;
}

std::vector<CandidateVisibility> MeasureCandidateVisibility(const ViewRenderer& renderer, const VoxelGrid& grid,
                                                            const std::vector<uint32_t>& surface, const PinholeCamera& camera,
                                                            const std::vector<Eigen::Isometry3d>& world_from_camera,
                                                            const RenderOptions& render, const ViewSelectionOptions& options) {
  std::vector<int32_t> surface_id(grid.size(), -1);
  for (size_t s = 0; s < surface.size(); ++s) surface_id[surface[s]] = int32_t(s);
  const int ds = options.visibility_downscale;
  const PinholeCamera small = PinholeCamera::FromHorizontalFov(std::max(1, camera.width / ds), std::max(1, camera.height / ds),
                                                               camera.HorizontalFovDeg());
  const double min_cos = std::cos(options.max_incidence_deg * M_PI / 180.0);
  std::vector<CandidateVisibility> out(world_from_camera.size());
  tbb::parallel_for(size_t(0), world_from_camera.size(), [&](size_t c) {
    RenderedView view;
    CandidateVisibility& cv = out[c];
    if (!renderer.Render(small, world_from_camera[c], render, &view).ok()) return;  // Options are the caller's, checked.
    const Eigen::Matrix3d rotation = world_from_camera[c].linear();
    double depth_sum = 0;
    size_t hits = 0;
    std::array<int, 3> cell;
    for (int y = 0; y < small.height; ++y)
      for (int x = 0; x < small.width; ++x) {
        const size_t i = size_t(y) * small.width + x;
        if (view.primitive.data[i] < 0) continue;
        ++hits;
        depth_sum += view.depth.data[i];
        if (!grid.CellOfKey(view.voxel_key.data[i], &cell)) continue;
        const int32_t sid = surface_id[grid.Index(cell[0], cell[1], cell[2])];
        if (sid < 0) continue;
        const Eigen::Vector3d ray = (rotation * small.PixelRay(x, y)).normalized();
        const Eigen::Vector3d n(view.normal.data[3 * i], view.normal.data[3 * i + 1], view.normal.data[3 * i + 2]);
        if (-n.dot(ray) >= min_cos) cv.surface_ids.push_back(uint32_t(sid));
      }
    std::sort(cv.surface_ids.begin(), cv.surface_ids.end());
    cv.surface_ids.erase(std::unique(cv.surface_ids.begin(), cv.surface_ids.end()), cv.surface_ids.end());
    cv.surface_ids.shrink_to_fit();
    const size_t pixels = size_t(small.width) * size_t(small.height);
    cv.hit_fraction = pixels ? double(hits) / double(pixels) : 0.0;
    cv.mean_depth_m = hits ? depth_sum / double(hits) : 0.0;
  });
  return out;
}

ViewSelection SelectViewsBySetCover(const std::vector<std::vector<uint32_t>>& seen, size_t num_elements,
                                    const ViewSelectionOptions& options) {
  ViewSelection sel;
  sel.candidates = seen.size();
  sel.surface_voxels = num_elements;
  const int k = options.min_views_per_voxel;
  // Demand: min(k, candidates that see the element).
  std::vector<int> remaining(num_elements, 0);
  for (const auto& s : seen)
    for (uint32_t e : s) remaining[e] = std::min(k, remaining[e] + 1);
  int64_t total = 0;
  for (int r : remaining) {
    total += r;
    sel.coverable_voxels += r >= k;
  }
  const auto gain_of = [&](size_t c) {
    int64_t g = 0;
    for (uint32_t e : seen[c]) g += remaining[e] > 0;
    return g;
  };
  // Lazy greedy: a max-heap of (upper bound of the gain, candidate), larger gain first, then lower index.
  using Entry = std::pair<int64_t, int>;
  const auto worse = [](const Entry& a, const Entry& b) { return a.first != b.first ? a.first < b.first : a.second > b.second; };
  std::priority_queue<Entry, std::vector<Entry>, decltype(worse)> heap(worse);
  for (size_t c = 0; c < seen.size(); ++c)
    if (!seen[c].empty()) heap.push({int64_t(seen[c].size()), int(c)});
  const double min_gain = std::max(1.0, options.min_gain_fraction * double(total));
  while (!heap.empty()) {
    const auto [bound, c] = heap.top();
    heap.pop();
    const int64_t g = gain_of(size_t(c));
    if (!heap.empty() && worse(Entry{g, c}, heap.top())) {  // Another view may gain more: look again later.
      heap.push({g, c});
      continue;
    }
    if (double(g) < min_gain) break;  // The best view adds too little.
    sel.chosen.push_back(c);
    for (uint32_t e : seen[size_t(c)])
      if (remaining[e] > 0) --remaining[e];
  }
  std::sort(sel.chosen.begin(), sel.chosen.end());
  // Coverage of the chosen views.
  std::vector<int> count(num_elements, 0);
  for (int c : sel.chosen)
    for (uint32_t e : seen[size_t(c)]) ++count[e];
  for (int n : count) {
    sel.covered_voxels += n >= k;
    sel.seen_voxels += n >= 1;
  }
  return sel;
}

}  // namespace semvox
