// Room-type CRF: view cones, the graph of floor cells and the energy (room_type_crf.h).
#include "rooms/room_type_crf.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_map>

#include "core/file_util.h"
#include "core/labels.h"
#include "rooms/room_type_crf_internal.h"

namespace semvox {

using namespace room_type_internal;

namespace room_type_internal {

void ConePixels(const FloorPlan& plan, const ViewRoomEvidence& v, std::vector<uint32_t>* stamp, uint32_t tag,
                std::vector<int>* out) {
  out->clear();
  const int W = plan.width(), H = plan.height();
  const double res = plan.resolution_m;
  if (W == 0 || H == 0 || !(v.max_range_m > 0) || !(v.hfov_rad > 0)) return;
  const double cx = (v.position.x() - plan.origin_x) / res, cy = H - (v.position.y() - plan.origin_y) / res;
  const double range_px = v.max_range_m / res;
  const double hfov = std::min(v.hfov_rad, 2 * M_PI);
  // Rays close enough that neighbouring rays are under half a pixel apart at the far end.
  const int rays = std::max(8, int(std::ceil(hfov * range_px * 2)) + 1);
  for (int r = 0; r < rays; ++r) {
    const double a = v.yaw_rad - hfov / 2 + hfov * r / (rays - 1);
    const double dx = std::cos(a), dy = -std::sin(a);  // Row 0 is the largest y.
    for (double t = 0; t <= range_px; t += 0.5) {
      const int x = int(std::floor(cx + dx * t)), y = int(std::floor(cy + dy * t));
      if (x < 0 || y < 0 || x >= W || y >= H) break;
      const FloorCell c = plan.at(x, y);
      if (c == FloorCell::kWall || c == FloorCell::kUnknown) break;
      const size_t i = size_t(y) * W + x;
      if ((*stamp)[i] != tag) (*stamp)[i] = tag, out->push_back(int(i));
    }
  }
}

std::vector<std::vector<float>> PairDeltas(const RoomTypeEnergy& e) {
  const RoomTypeGraph& g = *e.graph;
  std::vector<std::vector<float>> deltas(g.neighbours.size());
  if (e.variant.homogeneity == HomogeneityPotential::kNone) return deltas;
  const double scale = e.weights.homogeneity / g.pair_normaliser;
  for (size_t i = 0; i < g.neighbours.size(); ++i) {
    deltas[i].reserve(g.neighbours[i].size());
    for (const auto& [j, d] : g.neighbours[i]) {
      const bool seg = g.segment[i] == g.segment[size_t(j)];
      deltas[i].push_back(float(scale * (e.Pair(true, seg, d) - e.Pair(false, seg, d))));
    }
  }
  return deltas;
}

}  // namespace room_type_internal

Image<uint16_t> ProjectViewCones(const FloorPlan& plan, const std::vector<ViewRoomEvidence>& views) {
  Image<uint16_t> count(plan.width(), plan.height(), 1, 0);
  std::vector<uint32_t> stamp(count.data.size(), 0);
  std::vector<int> pixels;
  for (size_t v = 0; v < views.size(); ++v) {
    ConePixels(plan, views[v], &stamp, uint32_t(v + 1), &pixels);
    for (int i : pixels) count.data[size_t(i)] = uint16_t(std::min(65535, count.data[size_t(i)] + 1));
  }
  return count;
}

Result<RoomTypeGraph> BuildRoomTypeGraph(const FloorPlan& plan, const RoomSegmentation& rooms,
                                         const std::vector<ViewRoomEvidence>& views,
                                         const Image<uint16_t>& topview_labels, const RoomTypeModel& model,
                                         const RoomTypeCrfOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("room-type CRF: " + error);
  const int W = plan.width(), H = plan.height();
  if (rooms.room_extent_ids.width != W || rooms.room_extent_ids.height != H)
    return Status::InvalidInput("room-type CRF: the room segmentation is " + std::to_string(rooms.room_extent_ids.width) + "x" +
                                std::to_string(rooms.room_extent_ids.height) + ", the floor plan " + std::to_string(W) + "x" +
                                std::to_string(H) + " (both must be on the occupancy grid)");
  if (!topview_labels.empty() && (topview_labels.width != W || topview_labels.height != H))
    return Status::InvalidInput("room-type CRF: the semantic top view is " + std::to_string(topview_labels.width) + "x" +
                                std::to_string(topview_labels.height) + ", the floor plan " + std::to_string(W) + "x" +
                                std::to_string(H) + " (both must be on the occupancy grid)");
  for (size_t v = 0; v < views.size(); ++v) {
    double sum = 0;
    for (double p : views[v].p) {
      if (!(p >= 0) || !std::isfinite(p)) return Status::InvalidInput("room-type CRF: view " + std::to_string(v) + " has a negative or non-finite probability");
      sum += p;
    }
    if (!(sum > 0)) return Status::InvalidInput("room-type CRF: view " + std::to_string(v) + " has an all-zero distribution");
  }
  if (model.object_type.size() != size_t(kNumNyu40) || model.hom_log_prob.empty())
    return Status::InvalidInput("room-type CRF: incomplete model (object table or homogeneity statistics missing)");
  RoomTypeGraph g;
  g.width = W, g.height = H;
  g.node_of_pixel.assign(size_t(W) * H, -1);
  const double res = plan.resolution_m;
  const int cs = std::max(1, int(std::lround(options.cell_size_m / res)));
  const int bw = (W + cs - 1) / cs;
  std::unordered_map<uint64_t, int> node_of_key;
  std::vector<Eigen::Vector2d> sum_pos;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int r = rooms.room_extent_ids.at(x, y);
      if (r <= 0) continue;
      const uint64_t key = (uint64_t((y / cs) * bw + x / cs) << 16) | uint64_t(r);
      auto [it, inserted] = node_of_key.try_emplace(key, int(g.segment.size()));
      if (inserted) {
        g.segment.push_back(r);
        g.pixels.push_back(0);
        sum_pos.emplace_back(0, 0);
      }
      const int n = it->second;
      g.node_of_pixel[size_t(y) * W + x] = n;
      ++g.pixels[size_t(n)];
      sum_pos[size_t(n)] += Eigen::Vector2d(plan.origin_x + (x + 0.5) * res, plan.origin_y + (H - y - 0.5) * res);
    }
  const size_t N = g.segment.size();
  g.position.resize(N);
  for (size_t n = 0; n < N; ++n) g.position[n] = sum_pos[n] / g.pixels[n];

  // Scene evidence: the views' distributions over their cones (normalised), per pixel and view.
  std::vector<Dist> scene_sum(N, Dist{});
  std::vector<double> scene_count(N, 0), best_max(N, -1);
  g.votes.assign(N, Dist{});
  g.best_view.assign(N, Uniform());
  std::vector<uint32_t> stamp(size_t(W) * H, 0);
  std::vector<int> pixels;
  for (size_t v = 0; v < views.size(); ++v) {
    Dist p = views[v].p;
    const double s = std::accumulate(p.begin(), p.end(), 0.0);
    for (double& x : p) x /= s;
    const int top = ArgMax(p);
    ConePixels(plan, views[v], &stamp, uint32_t(v + 1), &pixels);
    for (int i : pixels) {
      const int n = g.node_of_pixel[size_t(i)];
      if (n < 0) continue;
      for (int y = 0; y < kRoomTypeLabels; ++y) scene_sum[size_t(n)][size_t(y)] += p[size_t(y)];
      scene_count[size_t(n)] += 1;
      g.votes[size_t(n)][size_t(top)] += 1;
      if (p[size_t(top)] > best_max[size_t(n)]) best_max[size_t(n)] = p[size_t(top)], g.best_view[size_t(n)] = p;
    }
  }
  g.scene.resize(N);
  g.covered.resize(N);
  for (size_t n = 0; n < N; ++n) {
    g.covered[n] = scene_count[n] > 0;
    if (!g.covered[n]) {
      g.scene[n] = Uniform();
      continue;
    }
    for (int y = 0; y < kRoomTypeLabels; ++y) g.scene[n][size_t(y)] = scene_sum[n][size_t(y)] / scene_count[n];
  }

  // Object evidence (Eq. 5): per room and object class, a distance transform from the class's top-view cells
  // inside the room; o = exp(-d^2 / 2 sigma^2), averaged over the node's pixels.
  g.objects.assign(N, {});
  for (auto& o : g.objects)
    for (auto& d : o) d.fill(0);
  if (!topview_labels.empty()) {
    const int num_rooms = rooms.num_rooms;
    std::vector<int> x0(num_rooms + 1, W), y0(num_rooms + 1, H), x1(num_rooms + 1, -1), y1(num_rooms + 1, -1);
    // A piece of furniture is an 8-connected group of object cells in one room. A class's evidence in a room
    // is scaled by its largest share of a piece over min_object_share, capped at 1: a patch of sofa or
    // television read on a bed counts little, a sofa of its own (or a kitchen counter in an open-plan room)
    // fully. 0: every class present counts fully (the paper's Eq. 5).
    auto object_at = [&](int x, int y) {
      const int k = topview_labels.at(x, y);
      return k > 0 && k < kNumNyu40 && ObjectGroupOf(k) >= 0 ? k : 0;
    };
    std::vector<std::vector<double>> weight(num_rooms + 1, std::vector<double>(kNumNyu40, 0.0));
    std::vector<uint8_t> in_piece(size_t(W) * H, 0);
    std::vector<size_t> members;
    std::vector<int> per_class(kNumNyu40, 0);
    for (int sy = 0; sy < H; ++sy)
      for (int sx = 0; sx < W; ++sx) {
        const size_t s0 = size_t(sy) * W + sx;
        const int r = rooms.room_extent_ids.data[s0];
        if (r <= 0 || r > num_rooms) continue;
        x0[r] = std::min(x0[r], sx), x1[r] = std::max(x1[r], sx), y0[r] = std::min(y0[r], sy), y1[r] = std::max(y1[r], sy);
        if (in_piece[s0] || !object_at(sx, sy)) continue;
        members.assign(1, s0);
        in_piece[s0] = 1;
        std::fill(per_class.begin(), per_class.end(), 0);
        for (size_t m = 0; m < members.size(); ++m) {
          const int px = int(members[m] % W), py = int(members[m] / W);
          ++per_class[size_t(object_at(px, py))];
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int nx = px + dx, ny = py + dy;
              if (nx < 0 || ny < 0 || nx >= W || ny >= H) continue;
              const size_t q = size_t(ny) * W + nx;
              if (in_piece[q] || rooms.room_extent_ids.data[q] != r || !object_at(nx, ny)) continue;
              in_piece[q] = 1;
              members.push_back(q);
            }
        }
        for (int k = 1; k < kNumNyu40; ++k) {
          if (!per_class[size_t(k)]) continue;
          const double share = per_class[size_t(k)] / double(members.size());
          const double w = options.min_object_share > 0 ? std::min(1.0, share / options.min_object_share) : 1.0;
          weight[size_t(r)][size_t(k)] = std::max(weight[size_t(r)][size_t(k)], w);
        }
      }
    // Rooms without any fixture cell (the absence term): the fixtures are object classes, so a room holds one
    // exactly where a piece above gave it a weight.
    const std::vector<int>& fixtures = R2vFixtureLabels();
    g.without_fixture.assign(N, false);
    for (size_t n = 0; n < N; ++n) {
      const std::vector<double>& present = weight[size_t(g.segment[n])];
      g.without_fixture[n] = std::none_of(fixtures.begin(), fixtures.end(), [&](int k) { return present[size_t(k)] > 0; });
    }
    const double sigma_px = options.object_sigma_m / res;
    tbb::parallel_for(1, num_rooms + 1, [&](int r) {
      if (x1[r] < 0) return;
      const cv::Rect roi(x0[r], y0[r], x1[r] - x0[r] + 1, y1[r] - y0[r] + 1);
      for (int k = 1; k < kNumNyu40; ++k) {
        const double w = weight[size_t(r)][size_t(k)];
        if (w <= 0) continue;
        cv::Mat1b src(roi.height, roi.width, uchar(255));
        for (int y = roi.y; y < roi.y + roi.height; ++y)
          for (int x = roi.x; x < roi.x + roi.width; ++x)
            if (rooms.room_extent_ids.at(x, y) == r && topview_labels.at(x, y) == k) src(y - roi.y, x - roi.x) = 0;
        cv::Mat1f dist;
        cv::distanceTransform(src, dist, cv::DIST_L2, cv::DIST_MASK_5);
        const int grp = ObjectGroupOf(k);
        for (int y = roi.y; y < roi.y + roi.height; ++y)
          for (int x = roi.x; x < roi.x + roi.width; ++x) {
            if (rooms.room_extent_ids.at(x, y) != r) continue;
            const int n = g.node_of_pixel[size_t(y) * W + x];
            const double d = dist(y - roi.y, x - roi.x);
            const double o = w * std::exp(-d * d / (2 * sigma_px * sigma_px)) / g.pixels[size_t(n)];
            // Nodes belong to exactly one room, so rooms write disjoint nodes.
            for (int t = 0; t < kRoomTypeLabels; ++t) g.objects[size_t(n)][size_t(grp)][size_t(t)] += o * model.object_type[size_t(k)][size_t(t)];
          }
      }
    });
  }

  // Pairs within max_pair_distance_m: a bucket grid over node positions.
  g.neighbours.assign(N, {});
  const double R = options.max_pair_distance_m;
  std::unordered_map<int64_t, std::vector<int>> buckets;
  auto bucket = [&](const Eigen::Vector2d& p) {
    return std::pair<int64_t, int64_t>(int64_t(std::floor(p.x() / R)), int64_t(std::floor(p.y() / R)));
  };
  for (size_t n = 0; n < N; ++n) {
    const auto [bx, by] = bucket(g.position[n]);
    buckets[(bx << 32) ^ (by & 0xffffffff)].push_back(int(n));
  }
  tbb::parallel_for(size_t(0), N, [&](size_t n) {
    const auto [bx, by] = bucket(g.position[n]);
    for (int64_t dy = -1; dy <= 1; ++dy)
      for (int64_t dx = -1; dx <= 1; ++dx) {
        const auto it = buckets.find(((bx + dx) << 32) ^ ((by + dy) & 0xffffffff));
        if (it == buckets.end()) continue;
        for (int m : it->second) {
          if (size_t(m) == n) continue;
          const double d = (g.position[n] - g.position[size_t(m)]).norm();
          if (d <= R) g.neighbours[n].emplace_back(m, float(d));
        }
      }
    std::sort(g.neighbours[n].begin(), g.neighbours[n].end());
  });
  // The expected neighbour count of an interior node: the disc's area over a node's area.
  g.pair_normaliser = std::max(1.0, M_PI * R * R / (cs * res * cs * res));
  return g;
}

double RoomTypeEnergy::Scene(int i, int y) const {
  const Dist& s = graph->scene[size_t(i)];
  if (variant.scene == ScenePotential::kCnn) return s[size_t(y)];  // Eq. 2.
  double v = 0;                                                     // Eq. 3.
  for (int l = 0; l < kRoomTypeLabels; ++l) v += model->confusion[size_t(l)][size_t(y)] * s[size_t(l)];
  return v;
}

double RoomTypeEnergy::Object(int i, int g, int y) const { return graph->objects[size_t(i)][size_t(g)][size_t(y)]; }

double RoomTypeEnergy::SceneTerm(int i, int y) const { return weights.scene * Scene(i, y); }

double RoomTypeEnergy::ObjectTerm(int i, int g, int y) const { return weights.objects[size_t(g)] * Object(i, g, y); }

double RoomTypeEnergy::ShapeTerm(int i, int y) const {
  return graph->shape.empty() ? 0.0 : options.shape_weight * graph->shape[size_t(i)][size_t(y)];
}

double RoomTypeEnergy::FixtureTerm(int i, int y) const {
  if (graph->without_fixture.empty() || !graph->without_fixture[size_t(i)]) return 0.0;
  return options.fixture_absence_weight * model->no_fixture_log_prob[size_t(y)];
}

double RoomTypeEnergy::Unary(int i, int y) const {
  double u = SceneTerm(i, y);
  if (variant.objects)
    for (int g = 0; g < kNumObjectGroups; ++g) u += ObjectTerm(i, g, y);
  if (!graph->shape.empty()) u += ShapeTerm(i, y);
  u += FixtureTerm(i, y);
  return u;
}

double RoomTypeEnergy::Pair(bool same_type, bool same_segment, double distance_m) const {
  switch (variant.homogeneity) {
    case HomogeneityPotential::kNone:
      return 0;
    case HomogeneityPotential::kStatistics: {
      const size_t bins = model->hom_log_prob.size();
      const size_t b = std::min(bins - 1, size_t(std::max(0.0, distance_m / model->hom_bin_m)));
      return model->hom_log_prob[b][size_t(Event(same_type, same_segment))];
    }
    case HomogeneityPotential::kGaussian: {
      const double k = std::exp(-distance_m * distance_m / (2 * options.gauss_sigma_m * options.gauss_sigma_m));
      const double c = same_segment ? options.gauss_same_segment : options.gauss_other_segment;
      return (same_type ? c : -c) * k;
    }
  }
  return 0;
}

double RoomTypeEnergy::Total(const std::vector<int>& labels) const {
  double e = 0;
  const RoomTypeGraph& g = *graph;
  for (size_t i = 0; i < labels.size(); ++i) {
    e += Unary(int(i), labels[i]);
    if (variant.homogeneity == HomogeneityPotential::kNone) continue;
    for (const auto& [j, d] : g.neighbours[i])
      if (size_t(j) > i)
        e += weights.homogeneity / g.pair_normaliser * Pair(labels[i] == labels[size_t(j)], g.segment[i] == g.segment[size_t(j)], d);
  }
  return e;
}

}  // namespace semvox
