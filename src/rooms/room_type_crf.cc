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

namespace semvox {
namespace {

using Dist = std::array<double, kRoomTypeLabels>;

Dist Uniform() {
  Dist d;
  d.fill(1.0 / kRoomTypeLabels);
  return d;
}

int ArgMax(const Dist& d) { return int(std::max_element(d.begin(), d.end()) - d.begin()); }

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Pixels (indices) covered by one view's cone: rays over the field of view, marched in half-pixel steps from
// the camera, stopped by walls, unknown cells and the plan's border (2D ray casting on the plan).
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

// The 4 events of Eq. 6: 0 same type & same segment, 1 different & same, 2 same & different segment, 3 both different.
int Event(bool same_type, bool same_segment) { return same_segment ? (same_type ? 0 : 1) : (same_type ? 2 : 3); }

// Per-neighbour difference between the same-type and different-type pair potential (the only part of the pair
// term a node's conditional depends on), times w_hom / normaliser.
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

}  // namespace

int ObjectGroupOf(int nyu40) {
  switch (nyu40) {
    case 4: case 6:  // bed, sofa: group 4.
      return 3;
    case 12: case 24: case 28: case 33: case 34: case 36:  // counter, refrigerator, shower curtain, toilet, sink, bathtub.
      return 2;
    case 3: case 5: case 7: case 10: case 14: case 15: case 17: case 32: case 39:  // cabinet, chair, table, bookshelf,
      return 0;                                                                     // desk, shelves, dresser, night stand, otherfurniture.
    case 11: case 18: case 19: case 20: case 21: case 23: case 25: case 26: case 27: case 29: case 30: case 35: case 37:
    case 40:  // picture, pillow, mirror, floor mat, clothes, books, tv, paper, towel, box, whiteboard, lamp, bag, otherprop.
      return 1;
    default:  // unlabelled, wall, floor, door, window, blinds, curtain, ceiling, person, otherstructure.
      return -1;
  }
}

const char* ScenePotentialName(ScenePotential s) { return s == ScenePotential::kCnn ? "cnn" : "conf"; }
const char* HomogeneityPotentialName(HomogeneityPotential h) {
  return h == HomogeneityPotential::kNone ? "none" : h == HomogeneityPotential::kStatistics ? "stat" : "gauss";
}
bool ParseScenePotential(const std::string& name, ScenePotential* out) {
  if (name == "cnn") return *out = ScenePotential::kCnn, true;
  if (name == "conf") return *out = ScenePotential::kConfusion, true;
  return false;
}
bool ParseHomogeneityPotential(const std::string& name, HomogeneityPotential* out) {
  if (name == "none") return *out = HomogeneityPotential::kNone, true;
  if (name == "stat") return *out = HomogeneityPotential::kStatistics, true;
  if (name == "gauss") return *out = HomogeneityPotential::kGaussian, true;
  return false;
}

std::string RoomTypeVariant::Name() const {
  return std::string(ScenePotentialName(scene)) + "+" + HomogeneityPotentialName(homogeneity) + (objects ? "+obj" : "");
}

RoomTypeWeights RoomTypeModel::WeightsFor(const RoomTypeVariant& variant) const {
  for (const auto& [name, w] : weights)
    if (name == variant.Name()) return w;
  return RoomTypeWeights{};
}

void RoomTypeModel::SetWeights(const RoomTypeVariant& variant, const RoomTypeWeights& w) {
  for (auto& [name, old] : weights)
    if (name == variant.Name()) return void(old = w);
  weights.emplace_back(variant.Name(), w);
}

RoomTypeModel RoomTypeModel::Uninformative() {
  RoomTypeModel m;
  for (int l = 0; l < kRoomTypeLabels; ++l)
    for (int y = 0; y < kRoomTypeLabels; ++y) m.confusion[size_t(l)][size_t(y)] = l == y ? 1 : 0;
  m.object_type.assign(kNumNyu40, Uniform());
  m.hom_log_prob.assign(12, {std::log(0.5), std::log(0.5), std::log(0.5), std::log(0.5)});
  m.provenance = "uninformative";
  return m;
}

std::string RoomTypeModelToJson(const RoomTypeModel& m) {
  using nlohmann::ordered_json;
  ordered_json j;
  j["format"] = "semvox room-type CRF model 1";
  j["provenance"] = m.provenance;
  j["confusion_true_given_view_argmax"] = m.confusion;
  j["object_type_given_object"] = m.object_type;
  j["hom_bin_m"] = m.hom_bin_m;
  j["hom_log_prob"] = m.hom_log_prob;
  ordered_json w = ordered_json::object();
  for (const auto& [name, x] : m.weights)
    w[name] = {{"scene", x.scene}, {"objects", x.objects}, {"homogeneity", x.homogeneity}};
  j["weights"] = w;
  j["dense_crf"] = {{"w_appearance", m.dense.w_appearance}, {"theta_alpha_m", m.dense.theta_alpha_m},
                    {"w_smooth", m.dense.w_smooth}, {"theta_gamma_m", m.dense.theta_gamma_m}};
  return j.dump(1) + "\n";
}

Status SaveRoomTypeModel(const RoomTypeModel& model, const std::string& path) {
  return WriteFileAtomic(path, RoomTypeModelToJson(model));
}

Result<RoomTypeModel> LoadRoomTypeModel(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  RoomTypeModel m;
  try {
    const nlohmann::json j = nlohmann::json::parse(bytes);
    if (j.at("format").get<std::string>() != "semvox room-type CRF model 1") throw std::runtime_error("unknown format");
    m.provenance = j.value("provenance", "");
    m.confusion = j.at("confusion_true_given_view_argmax").get<decltype(m.confusion)>();
    m.object_type = j.at("object_type_given_object").get<decltype(m.object_type)>();
    m.hom_bin_m = j.at("hom_bin_m").get<double>();
    m.hom_log_prob = j.at("hom_log_prob").get<decltype(m.hom_log_prob)>();
    for (const auto& [name, x] : j.at("weights").items()) {
      RoomTypeWeights w;
      w.scene = x.at("scene").get<double>();
      w.objects = x.at("objects").get<decltype(w.objects)>();
      w.homogeneity = x.at("homogeneity").get<double>();
      m.weights.emplace_back(name, w);
    }
    const auto& d = j.at("dense_crf");
    m.dense = {d.at("w_appearance").get<double>(), d.at("theta_alpha_m").get<double>(), d.at("w_smooth").get<double>(),
               d.at("theta_gamma_m").get<double>()};
    if (m.object_type.size() != size_t(kNumNyu40) || m.hom_log_prob.empty() || !(m.hom_bin_m > 0))
      throw std::runtime_error("object table needs 41 rows, homogeneity table at least one bin");
  } catch (const std::exception& e) {
    return Status::InvalidInput(FileError(path, std::string("not a room-type CRF model: ") + e.what(),
                                          "write it with `semvox train`"));
  }
  return m;
}

bool RoomTypeCrfOptions::Check(std::string* error) const { return CheckOptions(*this, Options(), error); }

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
    std::vector<std::vector<bool>> has(num_rooms + 1, std::vector<bool>(kNumNyu40, false));
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int r = rooms.room_extent_ids.at(x, y);
        if (r <= 0 || r > num_rooms) continue;
        x0[r] = std::min(x0[r], x), x1[r] = std::max(x1[r], x), y0[r] = std::min(y0[r], y), y1[r] = std::max(y1[r], y);
        const int k = topview_labels.at(x, y);
        if (k > 0 && k < kNumNyu40 && ObjectGroupOf(k) >= 0) has[r][size_t(k)] = true;
      }
    const double sigma_px = options.object_sigma_m / res;
    tbb::parallel_for(1, num_rooms + 1, [&](int r) {
      if (x1[r] < 0) return;
      const cv::Rect roi(x0[r], y0[r], x1[r] - x0[r] + 1, y1[r] - y0[r] + 1);
      for (int k = 1; k < kNumNyu40; ++k) {
        if (!has[r][size_t(k)]) continue;
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
            const double o = std::exp(-d * d / (2 * sigma_px * sigma_px)) / g.pixels[size_t(n)];
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

double RoomTypeEnergy::Unary(int i, int y) const {
  double u = weights.scene * Scene(i, y);
  if (variant.objects)
    for (int g = 0; g < kNumObjectGroups; ++g) u += weights.objects[size_t(g)] * Object(i, g, y);
  if (!graph->shape.empty()) u += options.shape_weight * graph->shape[size_t(i)][size_t(y)];
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

std::vector<Dist> GibbsMarginals(const RoomTypeEnergy& energy, const RoomTypeCrfOptions& options, GibbsSummary* summary) {
  const auto t0 = std::chrono::steady_clock::now();
  const RoomTypeGraph& g = *energy.graph;
  const size_t N = g.segment.size();
  std::vector<Dist> unary(N);
  for (size_t i = 0; i < N; ++i)
    for (int y = 0; y < kRoomTypeLabels; ++y) unary[i][size_t(y)] = energy.Unary(int(i), y);
  const std::vector<std::vector<float>> deltas = PairDeltas(energy);
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  auto draw = [&](const Dist& w) {  // w: unnormalised non-negative weights.
    double total = std::accumulate(w.begin(), w.end(), 0.0), u = uni(rng) * total;
    for (int y = 0; y < kRoomTypeLabels; ++y)
      if ((u -= w[size_t(y)]) <= 0) return y;
    return kRoomTypeLabels - 1;
  };
  // Initialisation: each node drawn from its scene distribution (Sec. V-C).
  std::vector<int> labels(N);
  for (size_t i = 0; i < N; ++i) labels[i] = draw(g.scene[i]);
  std::vector<int> order(N);
  std::iota(order.begin(), order.end(), 0);
  std::vector<Dist> counts(N, Dist{});
  const int sweeps = options.burn_in_sweeps + options.sample_sweeps;
  for (int s = 0; s < sweeps; ++s) {
    std::shuffle(order.begin(), order.end(), rng);  // Randomised order (Sec. V-C).
    for (int i : order) {
      Dist score = unary[size_t(i)];
      if (!deltas[size_t(i)].empty()) {
        const auto& nb = g.neighbours[size_t(i)];
        const auto& dl = deltas[size_t(i)];
        for (size_t k = 0; k < nb.size(); ++k) score[size_t(labels[size_t(nb[k].first)])] += dl[k];
      }
      const double mx = *std::max_element(score.begin(), score.end());
      for (double& v : score) v = std::exp(v - mx);
      labels[size_t(i)] = draw(score);
    }
    if (s >= options.burn_in_sweeps)
      for (size_t i = 0; i < N; ++i) counts[i][size_t(labels[i])] += 1;
  }
  for (auto& c : counts)
    for (double& v : c) v /= options.sample_sweeps;
  if (summary) summary->sweeps = sweeps, summary->seconds = Seconds(t0);
  return counts;
}

std::vector<Dist> ExactMarginals(const RoomTypeEnergy& energy, int num_labels_used) {
  const size_t N = energy.graph->segment.size();
  const int L = std::clamp(num_labels_used, 1, kRoomTypeLabels);
  std::vector<Dist> m(N, Dist{});
  if (N == 0 || N > 8) return m;
  std::vector<int> labels(N, 0);
  std::vector<double> energies;
  std::vector<std::vector<int>> configs;
  double mx = -1e300;
  while (true) {
    const double e = energy.Total(labels);
    energies.push_back(e), configs.push_back(labels);
    mx = std::max(mx, e);
    size_t k = 0;
    while (k < N && ++labels[k] == L) labels[k++] = 0;
    if (k == N) break;
  }
  double z = 0;
  for (size_t c = 0; c < configs.size(); ++c) {
    const double p = std::exp(energies[c] - mx);
    z += p;
    for (size_t i = 0; i < N; ++i) m[i][size_t(configs[c][i])] += p;
  }
  for (auto& d : m)
    for (double& v : d) v /= z;
  return m;
}

std::vector<Dist> MajorityVoting(const RoomTypeGraph& g) {
  std::unordered_map<int, Dist> per_segment;
  for (size_t n = 0; n < g.segment.size(); ++n) {
    Dist& s = per_segment[g.segment[n]];
    for (int y = 0; y < kRoomTypeLabels; ++y) s[size_t(y)] += g.votes[n][size_t(y)];
  }
  std::vector<Dist> out(g.segment.size(), Dist{});
  for (size_t n = 0; n < g.segment.size(); ++n) {
    const Dist& s = per_segment[g.segment[n]];
    if (*std::max_element(s.begin(), s.end()) > 0) out[n][size_t(ArgMax(s))] = 1;  // No votes: no type.
  }
  return out;
}

std::vector<Dist> DenseGaussianCrf(const RoomTypeGraph& g, const DenseCrfParams& params, int iterations) {
  const size_t N = g.segment.size();
  std::vector<Dist> unary(N), q(N), next(N);
  for (size_t n = 0; n < N; ++n) {
    for (int y = 0; y < kRoomTypeLabels; ++y) unary[n][size_t(y)] = std::log(std::max(1e-3, g.best_view[n][size_t(y)]));
    q[n] = g.best_view[n];
  }
  const double a2 = 2 * params.theta_alpha_m * params.theta_alpha_m, g2 = 2 * params.theta_gamma_m * params.theta_gamma_m;
  for (int it = 0; it < iterations; ++it) {
    // Mean field (Kraehenbuehl & Koltun 2011) with a Potts compatibility: a label gains the kernel-weighted
    // belief of its neighbours in that label (the pair sum over the expected neighbour count, as the Gibbs CRF).
    tbb::parallel_for(size_t(0), N, [&](size_t n) {
      Dist msg{};
      for (const auto& [m, d] : g.neighbours[n]) {
        const double d2 = double(d) * d;
        double k = params.w_smooth * std::exp(-d2 / g2);
        if (g.segment[n] == g.segment[size_t(m)]) k += params.w_appearance * std::exp(-d2 / a2);
        for (int y = 0; y < kRoomTypeLabels; ++y) msg[size_t(y)] += k * q[size_t(m)][size_t(y)];
      }
      Dist e;
      for (int y = 0; y < kRoomTypeLabels; ++y) e[size_t(y)] = unary[n][size_t(y)] + msg[size_t(y)] / g.pair_normaliser;
      const double mx = *std::max_element(e.begin(), e.end());
      double z = 0;
      for (double& v : e) z += (v = std::exp(v - mx));
      for (double& v : e) v /= z;
      next[n] = e;
    });
    q.swap(next);
  }
  return q;
}

RoomTypeResult AssignRoomTypes(const RoomTypeGraph& graph, const RoomSegmentation& rooms, const FloorPlan& plan,
                               std::vector<Dist> marginals, const RoomTypeCrfOptions& options) {
  RoomTypeResult out;
  const int W = graph.width, H = graph.height;
  const double cell_area = plan.resolution_m * plan.resolution_m;
  out.pixel_types = ImageU16(W, H, 1, 0);
  auto node_type = [&](int n) {
    const Dist& m = marginals[size_t(n)];
    return *std::max_element(m.begin(), m.end()) > 0 ? ArgMax(m) + 1 : 0;
  };
  for (size_t i = 0; i < size_t(W) * H; ++i)
    if (const int n = graph.node_of_pixel[i]; n >= 0) out.pixel_types.data[i] = uint16_t(node_type(n));
  out.rooms = rooms;
  // Aggregated marginals per room (pixel-weighted).
  auto aggregate = [&](const RoomSegmentation& segs, int num) {
    std::vector<Dist> agg(size_t(num) + 1, Dist{});
    for (size_t i = 0; i < size_t(W) * H; ++i) {
      const int r = segs.room_extent_ids.data[i], n = graph.node_of_pixel[i];
      if (r <= 0 || r > num || n < 0) continue;
      for (int y = 0; y < kRoomTypeLabels; ++y) agg[size_t(r)][size_t(y)] += marginals[size_t(n)][size_t(y)];
    }
    return agg;
  };
  std::vector<Dist> agg = aggregate(rooms, rooms.num_rooms);
  std::vector<int> room_area(size_t(rooms.num_rooms) + 1, 0);
  for (uint16_t r : rooms.room_extent_ids.data)
    if (r > 0 && r <= rooms.num_rooms) ++room_area[r];
  // Split rule: 4-connected areas of one type other than the room's.
  std::vector<int> comp(size_t(W) * H, -1);
  int next_id = rooms.num_rooms;
  for (int r = 1; r <= rooms.num_rooms; ++r) {
    const Dist& a = agg[size_t(r)];
    if (*std::max_element(a.begin(), a.end()) <= 0) continue;
    const int room_type = ArgMax(a) + 1;
    for (int sy = 0; sy < H; ++sy)
      for (int sx = 0; sx < W; ++sx) {
        const size_t s = size_t(sy) * W + sx;
        if (rooms.room_extent_ids.data[s] != r || comp[s] >= 0) continue;
        const int t = out.pixel_types.data[s];
        if (t == 0 || t == room_type) continue;
        std::vector<size_t> area{s};
        comp[s] = int(s);
        double mean_p = 0;
        for (size_t k = 0; k < area.size(); ++k) {
          const size_t p = area[k];
          mean_p += marginals[size_t(graph.node_of_pixel[p])][size_t(t - 1)];
          const int px = int(p % W), py = int(p / W);
          const int nx[4] = {px - 1, px + 1, px, px}, ny[4] = {py, py, py - 1, py + 1};
          for (int d = 0; d < 4; ++d) {
            if (nx[d] < 0 || ny[d] < 0 || nx[d] >= W || ny[d] >= H) continue;
            const size_t q = size_t(ny[d]) * W + nx[d];
            if (comp[q] >= 0 || rooms.room_extent_ids.data[q] != r || out.pixel_types.data[q] != t) continue;
            comp[q] = int(s);
            area.push_back(q);
          }
        }
        mean_p /= double(area.size());
        if (double(area.size()) * cell_area < options.min_split_area_m2 ||
            double(area.size()) < options.min_split_fraction * room_area[size_t(r)] || mean_p < options.min_split_probability)
          continue;
        ++next_id;
        ++out.splits;
        for (size_t p : area) {
          out.rooms.room_extent_ids.data[p] = uint16_t(next_id);
          if (out.rooms.room_ids.data[p] == r) out.rooms.room_ids.data[p] = uint16_t(next_id);
        }
      }
  }
  out.rooms.num_rooms = next_id;
  // Source room of each split-off id.
  std::vector<int> source(size_t(next_id) + 1, 0);
  for (size_t i = 0; i < size_t(W) * H; ++i)
    if (const int r = out.rooms.room_extent_ids.data[i]; r > 0) source[size_t(r)] = rooms.room_extent_ids.data[i];
  agg = aggregate(out.rooms, next_id);
  for (int r = 1; r <= next_id; ++r) {
    RoomTypeAssignment a;
    a.id = r;
    a.source_room = source[size_t(r)] ? source[size_t(r)] : r;
    const double total = std::accumulate(agg[size_t(r)].begin(), agg[size_t(r)].end(), 0.0);
    if (total > 0) {
      for (int y = 0; y < kRoomTypeLabels; ++y) a.probabilities[size_t(y)] = agg[size_t(r)][size_t(y)] / total;
      std::array<int, kRoomTypeLabels> idx;
      std::iota(idx.begin(), idx.end(), 0);
      std::stable_sort(idx.begin(), idx.end(), [&](int i, int j) { return a.probabilities[size_t(i)] > a.probabilities[size_t(j)]; });
      a.type_id = idx[0] + 1, a.probability = a.probabilities[size_t(idx[0])];
      a.second_type_id = idx[1] + 1, a.second_probability = a.probabilities[size_t(idx[1])];
    }
    out.assignments.push_back(a);
  }
  out.node_marginals = std::move(marginals);
  return out;
}

std::vector<RoomShape> SetRoomShapeEvidence(const RoomSegmentation& rooms, const FloorPlan& plan, const RoomShapeModel& shapes,
                                            RoomTypeGraph* graph) {
  std::vector<RoomShape> measured = MeasureRoomShapes(rooms.room_extent_ids, rooms.num_rooms, plan.resolution_m);
  std::vector<Dist> ratio(measured.size());
  for (size_t r = 0; r < measured.size(); ++r) ratio[r] = LogLikelihoodRatios(shapes, measured[r]);
  graph->shape.assign(graph->segment.size(), Dist{});
  for (size_t i = 0; i < graph->segment.size(); ++i) {
    const int g = graph->segment[i];
    if (g >= 1 && size_t(g) <= ratio.size()) graph->shape[i] = ratio[size_t(g - 1)];
  }
  return measured;
}

Result<RoomTypeResult> InferRoomTypes(const FloorPlan& plan, const RoomSegmentation& rooms,
                                      const std::vector<ViewRoomEvidence>& views, const Image<uint16_t>& topview_labels,
                                      const RoomTypeModel& model, const RoomTypeCrfOptions& options, RoomTypeMethod method,
                                      const RoomShapeModel* shapes) {
  const auto t0 = std::chrono::steady_clock::now();
  Result<RoomTypeGraph> graph = BuildRoomTypeGraph(plan, rooms, views, topview_labels, model, options);
  if (!graph.ok()) return graph.status();
  std::vector<RoomShape> measured;
  if (shapes) measured = SetRoomShapeEvidence(rooms, plan, *shapes, &*graph);
  std::vector<Dist> marginals;
  switch (method) {
    case RoomTypeMethod::kMajorityVoting:
      marginals = MajorityVoting(*graph);
      break;
    case RoomTypeMethod::kDenseCrf:
      marginals = DenseGaussianCrf(*graph, model.dense);
      break;
    case RoomTypeMethod::kGibbsCrf: {
      RoomTypeEnergy e{&*graph, &model, options.variant, model.WeightsFor(options.variant), options};
      marginals = GibbsMarginals(e, options);
      break;
    }
  }
  RoomTypeResult r = AssignRoomTypes(*graph, rooms, plan, std::move(marginals), options);
  r.shapes = std::move(measured);
  r.seconds = Seconds(t0);
  return r;
}

// ---- Training ----------------------------------------------------------------------------------------------

void ObjectRoomCounts::Add(const ObjectRoomCounts& o) {
  for (int y = 0; y < kRoomTypeLabels; ++y) rooms[size_t(y)] += o.rooms[size_t(y)];
  for (size_t k = 0; k < with_object.size() && k < o.with_object.size(); ++k)
    for (int y = 0; y < kRoomTypeLabels; ++y) with_object[k][size_t(y)] += o.with_object[k][size_t(y)];
}

std::vector<Dist> ObjectTypeStatistics(const ObjectRoomCounts& c) {
  std::vector<Dist> out(kNumNyu40, Uniform());
  for (int k = 1; k < kNumNyu40 && size_t(k) < c.with_object.size(); ++k) {
    Dist p{};
    double z = 0, seen = 0;
    for (int y = 0; y < kRoomTypeLabels; ++y) {
      // P(k | y), smoothed (types without rooms get 0.1).
      p[size_t(y)] = (c.with_object[size_t(k)][size_t(y)] + 0.1) / (c.rooms[size_t(y)] + 1.0);
      seen += c.with_object[size_t(k)][size_t(y)];
    }
    if (seen == 0) continue;  // Never observed: uniform.
    for (double v : p) z += v;
    for (int y = 0; y < kRoomTypeLabels; ++y) out[size_t(k)][size_t(y)] = p[size_t(y)] / z;  // Uniform type prior.
  }
  return out;
}

std::vector<int> NodeTruth(const RoomTypeGraph& g, const ImageU16& truth) {
  std::vector<std::array<int, kRoomTypeLabels + 1>> c(g.segment.size(), std::array<int, kRoomTypeLabels + 1>{});
  for (size_t i = 0; i < g.node_of_pixel.size(); ++i)
    if (const int n = g.node_of_pixel[i]; n >= 0 && truth.data[i] >= 1 && truth.data[i] <= kRoomTypeLabels) ++c[size_t(n)][truth.data[i]];
  std::vector<int> out(g.segment.size(), -1);
  for (size_t n = 0; n < out.size(); ++n) {
    const auto it = std::max_element(c[n].begin() + 1, c[n].end());
    if (*it > 0) out[n] = int(it - c[n].begin()) - 1;
  }
  return out;
}

void LearnConfusion(const std::vector<RoomTypeTrainingScene>& scenes, RoomTypeModel* model) {
  std::array<Dist, kRoomTypeLabels> counts{};
  for (const RoomTypeTrainingScene& s : scenes) {
    std::vector<uint32_t> stamp(s.truth.data.size(), 0);
    std::vector<int> pixels;
    for (size_t v = 0; v < s.views.size(); ++v) {
      const int l = ArgMax(s.views[v].p);
      ConePixels(s.plan, s.views[v], &stamp, uint32_t(v + 1), &pixels);
      for (int i : pixels)
        if (const int t = s.truth.data[size_t(i)]; t >= 1 && t <= kRoomTypeLabels) counts[size_t(l)][size_t(t - 1)] += 1;
    }
  }
  for (int l = 0; l < kRoomTypeLabels; ++l) {
    const double z = std::accumulate(counts[size_t(l)].begin(), counts[size_t(l)].end(), 0.0) + kRoomTypeLabels;
    for (int y = 0; y < kRoomTypeLabels; ++y) model->confusion[size_t(l)][size_t(y)] = (counts[size_t(l)][size_t(y)] + 1) / z;
  }
}

void LearnHomogeneityStatistics(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeCrfOptions& options,
                                RoomTypeModel* model) {
  const int bins = std::max(1, int(std::ceil(options.max_pair_distance_m / model->hom_bin_m)));
  std::vector<std::array<double, 4>> n(size_t(bins), std::array<double, 4>{});
  RoomTypeModel flat = RoomTypeModel::Uninformative();
  for (const RoomTypeTrainingScene& s : scenes) {
    Result<RoomTypeGraph> g = BuildRoomTypeGraph(s.plan, s.rooms, {}, {}, flat, options);
    if (!g.ok()) continue;
    const std::vector<int> t = NodeTruth(*g, s.truth);
    for (size_t i = 0; i < t.size(); ++i) {
      if (t[i] < 0) continue;
      for (const auto& [j, d] : g->neighbours[i]) {
        if (t[size_t(j)] < 0) continue;
        const size_t b = std::min(size_t(bins - 1), size_t(d / model->hom_bin_m));
        n[b][size_t(Event(t[i] == t[size_t(j)], g->segment[i] == g->segment[size_t(j)]))] += 1;
      }
    }
  }
  model->hom_log_prob.assign(size_t(bins), {});
  for (int b = 0; b < bins; ++b) {
    // P(type relation | segment relation, distance): events 0/1 within a segment, 2/3 across segments.
    const auto& c = n[size_t(b)];
    model->hom_log_prob[size_t(b)] = {std::log((c[0] + 1) / (c[0] + c[1] + 2)), std::log((c[1] + 1) / (c[0] + c[1] + 2)),
                                      std::log((c[2] + 1) / (c[2] + c[3] + 2)), std::log((c[3] + 1) / (c[2] + c[3] + 2))};
  }
}

namespace {

constexpr int kNumFeatures = 2 + kNumObjectGroups;  // scene, obj1..4, hom.

using Features = std::array<double, kNumFeatures>;

RoomTypeWeights FromVector(const Features& f) {
  RoomTypeWeights w;
  w.scene = f[0];
  for (int g = 0; g < kNumObjectGroups; ++g) w.objects[size_t(g)] = f[size_t(1 + g)];
  w.homogeneity = f[5];
  return w;
}

// Joint feature vector psi(y) (Eq. 1 with unit weights), divided by the node count.
Features JointFeatures(const RoomTypeEnergy& e, const std::vector<int>& y) {
  Features f{};
  const RoomTypeGraph& g = *e.graph;
  for (size_t i = 0; i < y.size(); ++i) {
    f[0] += e.Scene(int(i), y[i]);
    if (e.variant.objects)
      for (int k = 0; k < kNumObjectGroups; ++k) f[size_t(1 + k)] += e.Object(int(i), k, y[i]);
    if (e.variant.homogeneity == HomogeneityPotential::kNone) continue;
    for (const auto& [j, d] : g.neighbours[i])
      if (size_t(j) > i) f[5] += e.Pair(y[i] == y[size_t(j)], g.segment[i] == g.segment[size_t(j)], d) / g.pair_normaliser;
  }
  for (double& v : f) v /= std::max<size_t>(1, y.size());
  return f;
}

// Loss-augmented inference by iterated conditional modes: argmax_y E(y) / N + loss(y), loss = pixel-weighted
// fraction of nodes whose label differs from the truth.
std::vector<int> LossAugmentedIcm(const RoomTypeEnergy& e, const std::vector<int>& truth, double total_pixels) {
  const RoomTypeGraph& g = *e.graph;
  const size_t N = truth.size();
  const std::vector<std::vector<float>> deltas = PairDeltas(e);
  std::vector<Dist> unary(N);
  for (size_t i = 0; i < N; ++i)
    for (int y = 0; y < kRoomTypeLabels; ++y)
      unary[i][size_t(y)] = e.Unary(int(i), y) / double(N) + (y != truth[i] ? g.pixels[i] / total_pixels : 0.0);
  std::vector<int> y(N);
  for (size_t i = 0; i < N; ++i) y[i] = ArgMax(unary[i]);
  for (int sweep = 0; sweep < 10; ++sweep) {
    bool changed = false;
    for (size_t i = 0; i < N; ++i) {
      Dist s = unary[i];
      for (size_t k = 0; k < g.neighbours[i].size() && !deltas[i].empty(); ++k)
        s[size_t(y[size_t(g.neighbours[i][k].first)])] += deltas[i][k] / double(N);
      const int best = ArgMax(s);
      if (best != y[i]) y[i] = best, changed = true;
    }
    if (!changed) break;
  }
  return y;
}

}  // namespace

RoomTypeWeights LearnWeightsSsvm(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                 const RoomTypeVariant& variant, const RoomTypeCrfOptions& options, const SsvmOptions& ssvm) {
  struct Prepared {
    RoomTypeGraph graph;
    std::vector<int> truth;
    double pixels = 0;
  };
  std::vector<Prepared> data;
  for (const RoomTypeTrainingScene& s : scenes) {
    Result<RoomTypeGraph> g = BuildRoomTypeGraph(s.plan, s.rooms, s.views, s.topview, model, options);
    if (!g.ok()) continue;
    Prepared p;
    p.graph = std::move(g).value();
    p.truth = NodeTruth(p.graph, s.truth);
    for (size_t i = 0; i < p.truth.size(); ++i) {
      if (p.truth[i] < 0) p.truth[i] = ArgMax(p.graph.scene[i]);  // Unscored nodes: no loss either way.
      p.pixels += p.graph.pixels[i];
    }
    data.push_back(std::move(p));
  }
  Features w = {1, 0.5, 0.5, 0.5, 0.5, variant.homogeneity == HomogeneityPotential::kNone ? 0.0 : 0.5};
  if (!variant.objects) w[1] = w[2] = w[3] = w[4] = 0;
  if (data.empty()) return FromVector(w);
  Features avg{};
  int averaged = 0, t = 0;
  std::mt19937_64 rng(ssvm.seed);
  std::vector<size_t> order(data.size());
  std::iota(order.begin(), order.end(), 0);
  for (int epoch = 0; epoch < ssvm.epochs; ++epoch) {
    std::shuffle(order.begin(), order.end(), rng);
    for (size_t idx : order) {
      const Prepared& p = data[idx];
      RoomTypeEnergy e{&p.graph, &model, variant, FromVector(w), options};
      const std::vector<int> y_hat = LossAugmentedIcm(e, p.truth, p.pixels);
      const Features f_hat = JointFeatures(e, y_hat), f_true = JointFeatures(e, p.truth);
      const double eta = ssvm.learning_rate / std::sqrt(double(++t));
      for (int k = 0; k < kNumFeatures; ++k) {
        const double grad = ssvm.regularisation * w[size_t(k)] + f_hat[size_t(k)] - f_true[size_t(k)];
        w[size_t(k)] = std::max(0.0, w[size_t(k)] - eta * grad);  // Potentials reward agreement: w >= 0.
      }
      if (!variant.objects) w[1] = w[2] = w[3] = w[4] = 0;
      if (variant.homogeneity == HomogeneityPotential::kNone) w[5] = 0;
      if (epoch >= ssvm.epochs / 2) {
        for (int k = 0; k < kNumFeatures; ++k) avg[size_t(k)] += w[size_t(k)];
        ++averaged;
      }
    }
  }
  for (double& v : avg) v /= std::max(1, averaged);  // Averaged iterate of the second half.
  return FromVector(avg);
}

RoomTypeWeights CalibrateWeightScale(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                     const RoomTypeVariant& variant, const RoomTypeWeights& weights,
                                     const RoomTypeCrfOptions& options, const std::vector<double>& scales,
                                     double* chosen_scale) {
  std::vector<RoomTypeGraph> graphs;
  std::vector<std::vector<int>> truths;
  for (const RoomTypeTrainingScene& s : scenes) {
    Result<RoomTypeGraph> g = BuildRoomTypeGraph(s.plan, s.rooms, s.views, s.topview, model, options);
    if (!g.ok()) continue;
    truths.push_back(NodeTruth(*g, s.truth));
    graphs.push_back(std::move(g).value());
  }
  // A zero vector has no direction to scale: fall back to the scene term alone.
  Features f = {weights.scene, weights.objects[0], weights.objects[1], weights.objects[2], weights.objects[3], weights.homogeneity};
  if (std::all_of(f.begin(), f.end(), [](double v) { return v <= 0; })) f[0] = 1;
  const double largest = *std::max_element(f.begin(), f.end());
  for (double& v : f) v /= largest;  // Direction only: the largest weight becomes 1.
  double best_acc = -1, best_scale = 1;
  for (double scale : scales) {
    Features sf = f;
    for (double& v : sf) v *= scale;
    const RoomTypeWeights w = FromVector(sf);
    double ok = 0, all = 0;
    for (size_t s = 0; s < graphs.size(); ++s) {
      const RoomTypeEnergy e{&graphs[s], &model, variant, w, options};
      const std::vector<Dist> m = GibbsMarginals(e, options);
      for (size_t n = 0; n < m.size(); ++n) {
        if (truths[s][n] < 0) continue;
        all += graphs[s].pixels[n];
        ok += ArgMax(m[n]) == truths[s][n] ? graphs[s].pixels[n] : 0;
      }
    }
    if (all > 0 && ok / all > best_acc + 1e-9) best_acc = ok / all, best_scale = scale;
  }
  if (chosen_scale) *chosen_scale = best_scale;
  for (double& v : f) v *= best_scale;
  return FromVector(f);
}

DenseCrfParams LearnDenseCrfParams(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                   const RoomTypeCrfOptions& options) {
  std::vector<RoomTypeGraph> graphs;
  std::vector<std::vector<int>> truths;
  for (const RoomTypeTrainingScene& s : scenes) {
    Result<RoomTypeGraph> g = BuildRoomTypeGraph(s.plan, s.rooms, s.views, {}, model, options);
    if (!g.ok()) continue;
    truths.push_back(NodeTruth(*g, s.truth));
    graphs.push_back(std::move(g).value());
  }
  DenseCrfParams best = model.dense;
  double best_acc = -1;
  for (double wa : {1.0, 3.0, 10.0, 30.0})
    for (double ta : {0.75, 1.5})
      for (double ws : {0.0, 1.0, 3.0})
        for (double tg : {0.25, 0.5}) {
          if (ws == 0 && tg != 0.25) continue;
          const DenseCrfParams p{wa, ta, ws, tg};
          double ok = 0, all = 0;
          for (size_t s = 0; s < graphs.size(); ++s) {
            const std::vector<Dist> q = DenseGaussianCrf(graphs[s], p);
            for (size_t n = 0; n < q.size(); ++n) {
              if (truths[s][n] < 0) continue;
              all += graphs[s].pixels[n];
              ok += ArgMax(q[n]) == truths[s][n] ? graphs[s].pixels[n] : 0;
            }
          }
          if (all > 0 && ok / all > best_acc) best_acc = ok / all, best = p;
        }
  return best;
}

void RoomTypeAccuracy::Add(const ImageU16& predicted, const ImageU16& truth) {
  for (size_t i = 0; i < truth.data.size() && i < predicted.data.size(); ++i) {
    const int t = truth.data[i];
    if (t < 1 || t > kRoomTypeLabels) continue;
    total[size_t(t)] += 1;
    correct[size_t(t)] += predicted.data[i] == t;
  }
}

double RoomTypeAccuracy::Global() const {
  const double n = std::accumulate(total.begin(), total.end(), 0.0);
  return n > 0 ? std::accumulate(correct.begin(), correct.end(), 0.0) / n : 0.0;
}

double RoomTypeAccuracy::Average() const {
  double sum = 0;
  int types = 0;
  for (size_t t = 1; t < total.size(); ++t)
    if (total[t] > 0) sum += correct[t] / total[t], ++types;
  return types > 0 ? sum / types : 0.0;
}

ImageRgb8 RenderRoomTypes(const FloorPlan& plan, const ImageU16& pixel_types) {
  // One colour per room type id 1..12 (index 0: room space without a type).
  static const uint8_t kColours[kRoomTypeLabels + 1][3] = {
      {200, 200, 200}, {66, 146, 198}, {116, 196, 118}, {253, 174, 107}, {189, 189, 189}, {203, 24, 29},  {255, 217, 47},
      {158, 154, 200}, {231, 41, 138}, {102, 194, 165}, {140, 81, 10},   {191, 129, 45},  {90, 90, 90}};
  const int W = plan.width(), H = plan.height();
  ImageRgb8 img(W, H, 3, 255);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const FloorCell c = plan.at(x, y);
      const int t = pixel_types.empty() ? 0 : pixel_types.at(x, y);
      uint8_t rgb[3] = {255, 255, 255};
      if (c == FloorCell::kWall) rgb[0] = rgb[1] = rgb[2] = 32;
      else if (t >= 1 && t <= kRoomTypeLabels) {
        const double shade = c == FloorCell::kClutter ? 0.7 : 1.0;
        for (int k = 0; k < 3; ++k) rgb[k] = uint8_t(kColours[t][k] * shade);
      } else if (c == FloorCell::kFree || c == FloorCell::kDoor || c == FloorCell::kClutter) {
        for (int k = 0; k < 3; ++k) rgb[k] = kColours[0][k];
      }
      for (int k = 0; k < 3; ++k) img.at(x, y, k) = rgb[k];
    }
  return img;
}

}  // namespace semvox
