#include "voxelcrf/voxel_evidence.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <deque>

namespace semvox {

bool VoxelEvidenceOptions::Check(std::string* error) const { return CheckOptions(*this, Options(), error); }

size_t VoxelCrfNodes::count_state(VoxelState s) const {
  return size_t(std::count(initial_state.begin(), initial_state.end(), uint8_t(s)));
}

namespace {
constexpr int kBlock = 8;
}

void MarkPointNodes(const std::vector<uint32_t>& point_voxels, VoxelCrfNodes* nodes) {
  nodes->holds_point.clear();
  if (point_voxels.empty()) return;  // No points known: nothing to mark, and the CRF skips the constraint (a mesh uses MarkSurfaceNodes).
  nodes->holds_point.assign(nodes->size(), 0);
  for (uint32_t v : point_voxels)
    if (size_t(v) < nodes->node_of_voxel.size())
      if (const int32_t node = nodes->node_of_voxel[v]; node >= 0) nodes->holds_point[size_t(node)] = 1;
}

void MarkSurfaceNodes(VoxelCrfNodes* nodes) {
  nodes->holds_point.assign(nodes->size(), 0);
  for (size_t i = 0; i < nodes->size(); ++i) nodes->holds_point[i] = nodes->initial_state[i] == uint8_t(VoxelState::kOccupied);
}

VoxelCrfNodes SelectVoxelCrfNodes(const VoxelGrid& grid, double floor_z, double ceiling_z, const VoxelEvidenceOptions& options) {
  const auto& d = grid.dims();
  const double res = grid.resolution();
  const Eigen::Vector3d lo = grid.MinCorner();
  int z0 = 0, z1 = d[2];
  if (std::isfinite(floor_z)) z0 = std::clamp(int(std::floor((floor_z - lo.z()) / res)) - 2, 0, d[2]);
  if (std::isfinite(ceiling_z) && ceiling_z > floor_z) z1 = std::clamp(int(std::floor((ceiling_z - lo.z()) / res)) + 3, z0, d[2]);
  // Inside columns: a free voxel within interior_margin_cells (Chebyshev).
  const size_t cols = size_t(d[0]) * d[1];
  std::vector<uint8_t> free_col(cols, 0), inside(cols, 0);
  for (int z = z0; z < z1; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x)
        if (grid.state(grid.Index(x, y, z)) == VoxelState::kFree) free_col[size_t(y) * d[0] + x] = 1;
  const int m = options.interior_margin_cells;
  {
    // Separable Chebyshev dilation.
    std::vector<uint8_t> row(cols, 0);
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        uint8_t v = 0;
        for (int dx = -m; dx <= m && !v; ++dx) {
          const int xx = x + dx;
          if (xx >= 0 && xx < d[0]) v = free_col[size_t(y) * d[0] + xx];
        }
        row[size_t(y) * d[0] + x] = v;
      }
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        uint8_t v = 0;
        for (int dy = -m; dy <= m && !v; ++dy) {
          const int yy = y + dy;
          if (yy >= 0 && yy < d[1]) v = row[size_t(yy) * d[0] + x];
        }
        inside[size_t(y) * d[0] + x] = v;
      }
  }
  // Distance (6-connected steps through unknown voxels) from the occupied voxels, up to the band.
  const int band = int(std::ceil(options.completion_band_m / res - 1e-9));
  std::vector<uint8_t> selected(grid.size(), 0);
  std::vector<uint8_t> dist(band > 0 ? grid.size() : 0, 255);
  std::deque<uint32_t> queue;
  const int64_t stride[3] = {1, d[0], int64_t(d[0]) * d[1]};
  for (int z = z0; z < z1; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const size_t i = grid.Index(x, y, z);
        const VoxelState s = grid.state(i);
        if (s == VoxelState::kOccupied) {
          selected[i] = 1;
          if (band > 0) dist[i] = 0, queue.push_back(uint32_t(i));
        } else if (s == VoxelState::kFree) {
          // A free voxel next to an occupied one.
          const int c[3] = {x, y, z};
          bool next = false;
          for (int a = 0; a < 3 && !next; ++a)
            for (int sgn = -1; sgn <= 1 && !next; sgn += 2) {
              const int v = c[a] + sgn;
              if (v < 0 || v >= d[a] || (a == 2 && (v < z0 || v >= z1))) continue;
              next = grid.state(size_t(int64_t(i) + sgn * stride[a])) == VoxelState::kOccupied;
            }
          if (next) selected[i] = 1;
        }
      }
  while (!queue.empty()) {
    const uint32_t i = queue.front();
    queue.pop_front();
    if (dist[i] >= band) continue;
    const auto c = grid.Cell(i);
    for (int a = 0; a < 3; ++a)
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        const int v = c[size_t(a)] + sgn;
        if (v < 0 || v >= d[size_t(a)] || (a == 2 && (v < z0 || v >= z1))) continue;
        const size_t j = size_t(int64_t(i) + sgn * stride[a]);
        if (grid.state(j) != VoxelState::kUnknown || dist[j] != 255) continue;
        dist[j] = uint8_t(dist[i] + 1);
        const auto cj = grid.Cell(j);
        if (inside[size_t(cj[1]) * d[0] + cj[0]]) selected[j] = 1;
        queue.push_back(uint32_t(j));
      }
  }
  VoxelCrfNodes nodes;
  nodes.node_of_voxel.assign(grid.size(), -1);
  const int nb[3] = {(d[0] + kBlock - 1) / kBlock, (d[1] + kBlock - 1) / kBlock, (d[2] + kBlock - 1) / kBlock};
  for (int bz = 0; bz < nb[2]; ++bz)
    for (int by = 0; by < nb[1]; ++by)
      for (int bx = 0; bx < nb[0]; ++bx) {
        const uint32_t begin = uint32_t(nodes.voxel.size());
        for (int z = bz * kBlock; z < std::min(d[2], (bz + 1) * kBlock); ++z)
          for (int y = by * kBlock; y < std::min(d[1], (by + 1) * kBlock); ++y)
            for (int x = bx * kBlock; x < std::min(d[0], (bx + 1) * kBlock); ++x) {
              const size_t i = grid.Index(x, y, z);
              if (!selected[i]) continue;
              nodes.node_of_voxel[i] = int32_t(nodes.voxel.size());
              nodes.voxel.push_back(uint32_t(i));
              nodes.initial_state.push_back(uint8_t(grid.state(i)));
            }
        if (nodes.voxel.size() == begin) continue;
        nodes.block_begin.push_back(begin);
        const Eigen::Vector3d a = grid.CellCenter(bx * kBlock, by * kBlock, bz * kBlock);
        const Eigen::Vector3d b = grid.CellCenter(std::min(d[0], (bx + 1) * kBlock) - 1, std::min(d[1], (by + 1) * kBlock) - 1,
                                                  std::min(d[2], (bz + 1) * kBlock) - 1);
        nodes.block_centre.push_back((0.5 * (a + b)).cast<float>());
        nodes.block_radius.push_back(float(0.5 * (b - a).norm() + res));
      }
  nodes.block_begin.push_back(uint32_t(nodes.voxel.size()));
  return nodes;
}

EvidenceAccumulator::EvidenceAccumulator(const VoxelGrid& grid, const VoxelCrfNodes& nodes, int num_classes,
                                         const VoxelEvidenceOptions& options)
    : grid_(grid), nodes_(nodes), options_(options) {
  const size_t n = nodes.size();
  ev_.num_classes = num_classes;
  ev_.sigma_m = options.depth_sigma_voxels * grid.resolution();
  ev_.observing_views.assign(n, 0);
  ev_.hits.assign(n, 0);
  sum_f_.assign(n, 0.f);
  footprint_.assign(n, 0.f);
  colour_sum_.assign(n, {0.f, 0.f, 0.f});
  normal_sum_.assign(n, Eigen::Vector3f::Zero());
  centre_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto cell = grid.Cell(nodes.voxel[i]);
      centre_[i] = grid.CellCenter(cell[0], cell[1], cell[2]).cast<float>();
    }
  });
}

void EvidenceAccumulator::AddDepthView(const RenderedView& view) {
  const PinholeCamera& cam = view.camera;
  const Eigen::Isometry3d cfw = view.world_from_camera.inverse();
  const Eigen::Matrix3f R = cfw.linear().cast<float>();
  const Eigen::Vector3f t = cfw.translation().cast<float>();
  const float fx = float(cam.fx), fy = float(cam.fy), cx = float(cam.cx), cy = float(cam.cy);
  const int W = cam.width, H = cam.height;
  const float sigma = float(ev_.sigma_m), cutoff = 1.5f * sigma, inv2s2 = 1.0f / (2.0f * sigma * sigma);
  const float res = float(grid_.resolution());
  const float reach = 0.5f * std::sqrt(3.0f) * res;  // A ray reaches the voxel when its hit is no nearer than this.
  const float foot = fx * fy * res * res;
  // Frustum side planes through the camera centre (inward normals), camera frame.
  Eigen::Vector3f planes[4] = {Eigen::Vector3f(fx, 0, cx), Eigen::Vector3f(-fx, 0, float(W) - cx),
                               Eigen::Vector3f(0, fy, cy), Eigen::Vector3f(0, -fy, float(H) - cy)};
  for (auto& p : planes) p.normalize();
  // Occlusion culling: the deepest observed depth of each kTile x kTile pixel tile (-1 where no pixel has
  // depth). A block whose nearest point lies more than `cutoff` behind the deepest surface of every tile its
  // bounding box projects to holds only nodes the loop below would skip (occluded or unobserved), so it is
  // skipped whole: the sums are exactly those of visiting it.
  constexpr int kTile = 16;
  const int tw = (W + kTile - 1) / kTile, th = (H + kTile - 1) / kTile;
  tile_max_depth_.assign(size_t(tw) * size_t(th), -1.0f);
  tbb::parallel_for(tbb::blocked_range<int>(0, th), [&](const tbb::blocked_range<int>& r) {
    for (int ty = r.begin(); ty < r.end(); ++ty)
      for (int y = ty * kTile; y < std::min(H, (ty + 1) * kTile); ++y)
        for (int x = 0; x < W; ++x) {
          const float dm = view.depth.at(x, y);
          float& m = tile_max_depth_[size_t(ty) * size_t(tw) + size_t(x / kTile)];
          if (dm > 0 && dm > m) m = dm;
        }
  });
  // The deepest surface over the pixels a block (centre c, radius rad, camera frame) can project to; +inf
  // when the bound is not tight (the block reaches the camera plane).
  const auto deepest_behind = [&](const Eigen::Vector3f& c, float rad) {
    const float z_near = c.z() - rad, z_far = c.z() + rad;
    if (z_near <= 1e-3f) return std::numeric_limits<float>::infinity();
    // x / z over the box around the sphere: largest at (x_max, z_near) when x_max >= 0, else (x_max, z_far).
    const float x0 = c.x() - rad, x1 = c.x() + rad, y0 = c.y() - rad, y1 = c.y() + rad;
    const float u0 = fx * (x0 / (x0 <= 0 ? z_near : z_far)) + cx, u1 = fx * (x1 / (x1 >= 0 ? z_near : z_far)) + cx;
    const float v0 = fy * (y0 / (y0 <= 0 ? z_near : z_far)) + cy, v1 = fy * (y1 / (y1 >= 0 ? z_near : z_far)) + cy;
    const int ta = std::max(0, int(std::floor(u0)) - 1) / kTile, tb = std::min(W - 1, int(std::floor(u1)) + 1) / kTile;
    const int sa = std::max(0, int(std::floor(v0)) - 1) / kTile, sb = std::min(H - 1, int(std::floor(v1)) + 1) / kTile;
    float deepest = -1.0f;
    for (int ty = sa; ty <= sb; ++ty)
      for (int tx = ta; tx <= tb; ++tx) deepest = std::max(deepest, tile_max_depth_[size_t(ty) * size_t(tw) + size_t(tx)]);
    return deepest;
  };
  const size_t num_blocks = nodes_.block_centre.size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_blocks, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b) {
      const Eigen::Vector3f c = R * nodes_.block_centre[b] + t;
      const float rad = nodes_.block_radius[b];
      if (c.z() < -rad) continue;
      bool outside = false;
      for (const auto& p : planes) outside |= p.dot(c) < -rad;
      if (outside) continue;
      const float deepest = deepest_behind(c, rad);
      if (deepest < 0 || c.z() - rad - deepest > cutoff) continue;
      for (uint32_t i = nodes_.block_begin[b]; i < nodes_.block_begin[b + 1]; ++i) {
        const Eigen::Vector3f p = R * centre_[i] + t;
        const float z = p.z();
        if (z <= 1e-3f) continue;
        const float u = fx * p.x() / z + cx, v = fy * p.y() / z + cy;
        if (!(u >= 0 && u < float(W) && v >= 0 && v < float(H))) continue;
        const float dm = view.depth.at(int(u), int(v));
        if (dm <= 0) continue;  // Nothing observed along this pixel (hole or beyond range): no evidence.
        const float delta = z - dm;
        if (delta > cutoff) continue;  // Behind the observed surface: occluded in this view.
        sum_f_[i] += std::exp(-delta * delta * inv2s2);
        if (delta <= reach) footprint_[i] += foot / (z * z);
        if (ev_.observing_views[i] < 65535) ++ev_.observing_views[i];
      }
    }
  });
  // Hits: every pixel's key names the voxel its surface point lies in. The pixels' nodes are looked up in
  // parallel; the sums then run over the pixels in order (the same float sums as one pass).
  pixel_node_.resize(size_t(W) * size_t(H));
  tbb::parallel_for(tbb::blocked_range<int>(0, H, 8), [&](const tbb::blocked_range<int>& r) {
    std::array<int, 3> cell;
    for (int y = r.begin(); y < r.end(); ++y)
      for (int x = 0; x < W; ++x) {
        int32_t node = -1;
        if (view.hit(x, y) && grid_.CellOfKey(view.voxel_key.at(x, y), &cell)) node = nodes_.node_of_voxel[grid_.Index(cell[0], cell[1], cell[2])];
        pixel_node_[size_t(y) * size_t(W) + size_t(x)] = node;
      }
  });
  // Each part owns the nodes of one residue class and walks all pixels in order, so every node's sums run
  // over its pixels in pixel order, as one pass would, on both cores.
  constexpr int kParts = 2;
  tbb::parallel_for(0, kParts, [&](int part) {
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int32_t node = pixel_node_[size_t(y) * size_t(W) + size_t(x)];
        if (node < 0 || node % kParts != part) continue;
        ++ev_.hits[size_t(node)];
        for (int k = 0; k < 3; ++k) colour_sum_[size_t(node)][size_t(k)] += float(view.rgb.at(x, y, k));
        normal_sum_[size_t(node)] += Eigen::Vector3f(view.normal.at(x, y, 0), view.normal.at(x, y, 1), view.normal.at(x, y, 2));
      }
  });
  ++ev_.num_depth_views;
}

void EvidenceAccumulator::AddClassifiedView(const RenderedView& view, const Image<int32_t>* segment,
                                            std::span<const float> probabilities) {
  const int K = ev_.num_classes;
  const int view_id = ev_.num_classified_views++;
  const int32_t origin = int32_t(ev_.origins.size());
  ev_.origins.push_back(view.world_from_camera.translation().cast<float>());
  const Eigen::Matrix3f R = view.world_from_camera.linear().cast<float>();
  const int32_t row_base = int32_t(ev_.observations.size() / size_t(K));
  if (segment) ev_.observations.insert(ev_.observations.end(), probabilities.begin(), probabilities.end());
  const int s = options_.ray_stride;
  for (int y = s / 2; y < view.camera.height; y += s)
    for (int x = s / 2; x < view.camera.width; x += s) {
      if (!view.hit(x, y)) continue;
      const Eigen::Vector3d ray = view.camera.PixelRay(x, y);
      EvidenceRay r;
      r.direction = (R * ray.cast<float>()).normalized();
      r.max_t = float(view.depth.at(x, y) * ray.norm() + options_.ray_extension_m);
      r.origin = origin;
      r.view = view_id;
      r.px = int16_t(x / s);
      r.py = int16_t(y / s);
      if (segment) {
        r.observation = row_base + segment->at(x, y);
      } else {
        r.observation = int32_t(ev_.observations.size() / size_t(K));
        const size_t at = (size_t(y) * view.camera.width + x) * size_t(K);
        ev_.observations.insert(ev_.observations.end(), probabilities.begin() + ptrdiff_t(at), probabilities.begin() + ptrdiff_t(at + K));
      }
      ev_.rays.push_back(r);
    }
}

VoxelEvidence EvidenceAccumulator::Finish() && {
  const size_t n = nodes_.size();
  ev_.depth_agreement.assign(n, 0.f);
  ev_.density.assign(n, 0.f);
  ev_.reaching_rays = footprint_;
  ev_.colour.assign(n, {0, 0, 0});
  ev_.normal.assign(n, Eigen::Vector3f::Zero());
  for (size_t i = 0; i < n; ++i) {
    if (ev_.observing_views[i] > 0) {
      ev_.depth_agreement[i] = sum_f_[i] / float(ev_.observing_views[i]);
      ev_.density[i] = footprint_[i] > 0 ? std::min(1.0f, float(ev_.hits[i]) / footprint_[i]) : 0.f;
    }
    if (ev_.hits[i] > 0) {
      for (int k = 0; k < 3; ++k) ev_.colour[i][size_t(k)] = uint8_t(std::lround(colour_sum_[i][size_t(k)] / float(ev_.hits[i])));
      const float len = normal_sum_[i].norm();
      if (len > 1e-6f) ev_.normal[i] = normal_sum_[i] / len;
    }
  }
  return std::move(ev_);
}

}  // namespace semvox
