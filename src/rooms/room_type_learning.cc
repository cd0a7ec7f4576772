// Room-type CRF: statistics, confusion, structural-SVM weights and dense-CRF parameters (room_type_crf.h).
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

// ---- Training ----------------------------------------------------------------------------------------------

const std::vector<int>& R2vFixtureLabels() {
  static const std::vector<int> kLabels = {nyu40::kCounter, nyu40::kToilet, nyu40::kSink, nyu40::kBathtub};
  return kLabels;
}

std::array<double, kRoomTypeLabels> NoFixtureLogProb(const ObjectRoomCounts& c) {
  std::array<double, kRoomTypeLabels> out{};
  for (int y = 0; y < kRoomTypeLabels; ++y) out[size_t(y)] = std::log((c.without_fixture[size_t(y)] + 1) / (c.rooms[size_t(y)] + 2));
  return out;
}

void ObjectRoomCounts::Add(const ObjectRoomCounts& o) {
  for (int y = 0; y < kRoomTypeLabels; ++y) rooms[size_t(y)] += o.rooms[size_t(y)];
  for (int y = 0; y < kRoomTypeLabels; ++y) without_fixture[size_t(y)] += o.without_fixture[size_t(y)];
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
                                     double* chosen_scale, const RoomShapeModel* shapes) {
  std::vector<RoomTypeGraph> graphs;
  std::vector<std::vector<int>> truths;
  for (const RoomTypeTrainingScene& s : scenes) {
    Result<RoomTypeGraph> g = BuildRoomTypeGraph(s.plan, s.rooms, s.views, s.topview, model, options);
    if (!g.ok()) continue;
    if (shapes && options.shape_weight > 0) SetRoomShapeEvidence(s.rooms, s.plan, *shapes, &*g);
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

}  // namespace semvox
