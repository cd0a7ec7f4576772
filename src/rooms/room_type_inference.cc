// Room-type CRF: Gibbs marginals, exact marginals, the baselines and room assignment (room_type_crf.h).
#include "rooms/room_type_crf.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>
#include <unordered_map>

#include "core/file_util.h"
#include "core/labels.h"
#include "rooms/room_type_crf_internal.h"

namespace semvox {

using namespace room_type_internal;

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
  // The adjacency term: per room, the message from its neighbours' label shares at the start of each sweep.
  const size_t R = g.room_neighbours.size();
  const bool adjacency = R > 0 && energy.options.adjacency_weight > 0;
  std::vector<Dist> share(R, Dist{}), message(R, Dist{});
  auto refresh_messages = [&] {
    for (Dist& d : share) d.fill(0);
    for (size_t i = 0; i < N; ++i)
      if (const int r = g.segment[i]; r >= 1 && size_t(r) < R) share[size_t(r)][size_t(labels[i])] += g.pixels[i];
    for (Dist& d : share)
      if (const double total = std::accumulate(d.begin(), d.end(), 0.0); total > 0)
        for (double& v : d) v /= total;
    for (size_t r = 1; r < R; ++r) {
      message[r].fill(0);
      for (const int o : g.room_neighbours[r])
        if (o >= 1 && size_t(o) < R && size_t(o) != r) AddAdjacencyMessage(g.adjacency, share[size_t(o)], energy.options.adjacency_weight, &message[r]);
    }
  };
  const int sweeps = options.burn_in_sweeps + options.sample_sweeps;
  for (int s = 0; s < sweeps; ++s) {
    std::shuffle(order.begin(), order.end(), rng);  // Randomised order (Sec. V-C).
    if (adjacency) refresh_messages();
    for (int i : order) {
      Dist score = unary[size_t(i)];
      if (adjacency)
        if (const int r = g.segment[size_t(i)]; r >= 1 && size_t(r) < R)
          for (int y = 0; y < kRoomTypeLabels; ++y) score[size_t(y)] += message[size_t(r)][size_t(y)];
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

namespace {

// Pixel-weighted means of each unary term over the (output) rooms' nodes.
void AddRoomTerms(const RoomTypeGraph& graph, const RoomTypeEnergy& e, RoomTypeResult* r) {
  const size_t N = graph.segment.size();
  std::vector<Dist> scene(N), objects(N), shape(N), fixture(N);
  for (size_t i = 0; i < N; ++i)
    for (int y = 0; y < kRoomTypeLabels; ++y) {
      scene[i][size_t(y)] = e.SceneTerm(int(i), y);
      if (e.variant.objects)
        for (int g = 0; g < kNumObjectGroups; ++g) objects[i][size_t(y)] += e.ObjectTerm(int(i), g, y);
      shape[i][size_t(y)] = e.ShapeTerm(int(i), y);
      fixture[i][size_t(y)] = e.FixtureTerm(int(i), y);
    }
  std::vector<double> pixels(r->assignments.size() + 1, 0.0);
  const ImageU16& ids = r->rooms.room_extent_ids;
  for (size_t p = 0; p < ids.data.size() && p < graph.node_of_pixel.size(); ++p) {
    const int room = ids.data[p], n = graph.node_of_pixel[p];
    if (room < 1 || size_t(room) > r->assignments.size() || n < 0) continue;
    RoomTypeAssignment& a = r->assignments[size_t(room - 1)];
    pixels[size_t(room)] += 1;
    for (int y = 0; y < kRoomTypeLabels; ++y) {
      a.scene_term[size_t(y)] += scene[size_t(n)][size_t(y)];
      a.object_term[size_t(y)] += objects[size_t(n)][size_t(y)];
      a.shape_term[size_t(y)] += shape[size_t(n)][size_t(y)];
      a.fixture_term[size_t(y)] += fixture[size_t(n)][size_t(y)];
    }
  }
  for (size_t k = 0; k < r->assignments.size(); ++k)
    if (pixels[k + 1] > 0)
      for (int y = 0; y < kRoomTypeLabels; ++y) {
        r->assignments[k].scene_term[size_t(y)] /= pixels[k + 1];
        r->assignments[k].object_term[size_t(y)] /= pixels[k + 1];
        r->assignments[k].shape_term[size_t(y)] /= pixels[k + 1];
        r->assignments[k].fixture_term[size_t(y)] /= pixels[k + 1];
      }
}

}  // namespace

std::vector<RoomShape> SetRoomShapeEvidence(const RoomSegmentation& rooms, const FloorPlan& plan, const RoomShapeModel& shapes,
                                            RoomTypeGraph* graph) {
  std::vector<RoomShape> measured = MeasureRoomShapes(rooms.room_extent_ids, rooms.num_rooms, plan.resolution_m);
  std::vector<Dist> ratio(measured.size());
  for (size_t r = 0; r < measured.size(); ++r) ratio[r] = LogLikelihoodRatios(shapes, measured[r]);
  bool learnt = false;
  for (const auto& row : shapes.adjacency)
    for (double v : row) learnt = learnt || v != 0;
  graph->room_neighbours.clear();
  if (learnt) {
    graph->adjacency = shapes.adjacency;
    graph->room_neighbours.assign(measured.size() + 1, {});
    for (size_t r = 0; r < measured.size(); ++r) graph->room_neighbours[r + 1] = measured[r].neighbours;
  }
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
  std::optional<RoomTypeEnergy> energy;
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
      energy = e;
      break;
    }
  }
  RoomTypeResult r = AssignRoomTypes(*graph, rooms, plan, std::move(marginals), options);
  if (energy) AddRoomTerms(*graph, *energy, &r);
  r.shapes = std::move(measured);
  r.seconds = Seconds(t0);
  return r;
}

}  // namespace semvox
