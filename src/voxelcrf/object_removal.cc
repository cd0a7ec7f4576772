#include "voxelcrf/object_removal.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/ply.h"
#include "crf/energy.h"

namespace semvox {
namespace {

constexpr int kFace6[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

// Index of a neighbour cell, or -1 outside the grid.
inline int64_t Neighbour(const VoxelGrid& g, const std::array<int, 3>& c, int dx, int dy, int dz) {
  const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
  return g.Contains(x, y, z) ? int64_t(g.Index(x, y, z)) : -1;
}

}  // namespace

bool ObjectRemovalOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& m) { if (error) *error = m; return false; };
  if (!(completion_band_m >= 0)) return fail("completion_band_m = " + std::to_string(completion_band_m) + ". Violated constraint: >= 0");
  if (!(w_unseen >= 0)) return fail("w_unseen = " + std::to_string(w_unseen) + ". Violated constraint: >= 0");
  if (!(w_occupancy > 0)) return fail("w_occupancy = " + std::to_string(w_occupancy) + ". Violated constraint: > 0");
  if (!(w_semantic > 0 && w_semantic <= 2 * w_occupancy))
    return fail("w_semantic = " + std::to_string(w_semantic) + ". Violated constraint: 0 < w_semantic <= 2 w_occupancy (metric)");
  if (!(w_plane >= 0)) return fail("w_plane = " + std::to_string(w_plane) + ". Violated constraint: >= 0");
  if (!(planar_ratio > 0 && planar_ratio <= 1)) return fail("planar_ratio = " + std::to_string(planar_ratio) + ". Violated constraint: in (0, 1]");
  std::string e;
  if (!planes.Check(&e)) return fail("planes." + e);
  if (!solver.Check(&e)) return fail("solver." + e);
  return true;
}

std::vector<int32_t> LabelInstances(const VoxelGrid& grid, const SemanticMap& map, std::vector<ObjectInstance>* instances) {
  std::vector<int32_t> record_of(grid.size(), -1);
  for (size_t k = 0; k < map.occupied.size(); ++k) record_of[map.occupied[k].voxel] = int32_t(k);
  // Records are in grid-index order, so the first unvisited record starts the next component.
  std::vector<size_t> order(map.occupied.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return map.occupied[a].voxel < map.occupied[b].voxel; });
  std::vector<int32_t> id(map.occupied.size(), 0);
  if (instances) instances->clear();
  std::vector<size_t> stack;
  int next = 0;
  for (size_t start : order) {
    if (id[start]) continue;
    ObjectInstance inst;
    inst.id = ++next;
    inst.label = map.occupied[start].label;
    inst.min = inst.max = map.occupied[start].centre;
    id[start] = inst.id;
    stack.assign(1, start);
    while (!stack.empty()) {
      const size_t r = stack.back();
      stack.pop_back();
      ++inst.voxels;
      inst.min = inst.min.cwiseMin(map.occupied[r].centre), inst.max = inst.max.cwiseMax(map.occupied[r].centre);
      const auto c = grid.Cell(map.occupied[r].voxel);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int64_t n = Neighbour(grid, c, dx, dy, dz);
            if (n < 0 || record_of[size_t(n)] < 0) continue;
            const size_t q = size_t(record_of[size_t(n)]);
            if (id[q] || map.occupied[q].label != inst.label) continue;
            id[q] = inst.id;
            stack.push_back(q);
          }
    }
    if (instances) instances->push_back(inst);
  }
  return id;
}

std::vector<uint8_t> SelectForRemoval(const SemanticMap& map, const std::vector<int32_t>& instance_of_record,
                                      const RemovalSelection& selection) {
  std::vector<uint8_t> out(map.occupied.size(), 0);
  for (size_t k = 0; k < map.occupied.size(); ++k) {
    const int label = map.occupied[k].label;
    bool rm = std::find(selection.classes.begin(), selection.classes.end(), label) != selection.classes.end();
    if (!rm && k < instance_of_record.size())
      rm = std::find(selection.instances.begin(), selection.instances.end(), instance_of_record[k]) != selection.instances.end();
    if (!rm && selection.all_furniture && label > 0 && label < kNumNyu40) {
      const int group = Nyu40Labels()[size_t(label)].nyu4_id;
      rm = group == 3 || group == 4;  // furniture, props
    }
    out[k] = rm;
  }
  return out;
}

namespace {

// Phase 1: the removed records' voxels become unknown; the others stay occupied with their labels.
struct AfterRemoval {
  std::vector<uint16_t> label_of;  // Per voxel: the label of a remaining occupied voxel, 0 otherwise.
  std::vector<uint32_t> removed;   // Voxels of the removed records.
};
AfterRemoval ClearRemoved(const SemanticMap& map, const std::vector<uint8_t>& remove, VoxelGrid* g) {
  AfterRemoval a;
  a.label_of.assign(g->size(), 0);
  for (size_t k = 0; k < map.occupied.size(); ++k) {
    const auto& r = map.occupied[k];
    if (remove[k]) {
      g->set_state(r.voxel, VoxelState::kUnknown);
      a.removed.push_back(r.voxel);
    } else {
      g->set_state(r.voxel, VoxelState::kOccupied);
      a.label_of[r.voxel] = r.label;
    }
  }
  return a;
}

// Phase 2: the completion nodes, the removed voxels and the unknown voxels within `band` cells of them
// (26-neighbour BFS), sorted by voxel index.
std::vector<uint32_t> CompletionNodes(const VoxelGrid& g, const std::vector<uint32_t>& removed, int band) {
  std::vector<uint8_t> dist(g.size(), 255);
  std::vector<uint32_t> frontier = removed, next;
  for (uint32_t v : removed) dist[v] = 0;
  std::vector<uint32_t> node_voxel = removed;
  for (int step = 1; step <= band && !frontier.empty(); ++step) {
    next.clear();
    for (uint32_t v : frontier) {
      const auto c = g.Cell(v);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int64_t n = Neighbour(g, c, dx, dy, dz);
            if (n < 0 || dist[size_t(n)] != 255) continue;
            dist[size_t(n)] = uint8_t(step);
            next.push_back(uint32_t(n));
            if (g.state(size_t(n)) == VoxelState::kUnknown) node_voxel.push_back(uint32_t(n));
          }
    }
    frontier.swap(next);
  }
  std::sort(node_voxel.begin(), node_voxel.end());
  return node_voxel;
}

// Phase 3: planes of the remaining occupied voxels (normals by PCA of the occupied 5x5x5 neighbourhood,
// oriented towards the free 26-neighbours); per completion node the label of the largest plane whose hull
// covers it (0 = none). `node_of_voxel` receives the completion node of each voxel (-1 none).
std::vector<uint16_t> PlaneLabelsOfNodes(const VoxelGrid& g, const std::vector<uint16_t>& label_of, const std::vector<uint32_t>& node_voxel,
                                         const ObjectRemovalOptions& options, std::vector<int32_t>* node_of_voxel, size_t* planes_found,
                                         size_t* planes_used) {
  const size_t nvox = g.size();
  VoxelCrfNodes pn;
  pn.node_of_voxel.assign(nvox, -1);
  for (size_t i = 0; i < nvox; ++i)
    if (g.state(i) == VoxelState::kOccupied) {
      pn.node_of_voxel[i] = int32_t(pn.voxel.size());
      pn.voxel.push_back(uint32_t(i));
      pn.initial_state.push_back(uint8_t(VoxelState::kOccupied));
    }
  const size_t n_occ = pn.voxel.size();
  for (uint32_t v : node_voxel) {
    pn.node_of_voxel[v] = int32_t(pn.voxel.size());
    pn.voxel.push_back(v);
    pn.initial_state.push_back(uint8_t(VoxelState::kUnknown));
  }
  pn.block_begin = {0, uint32_t(pn.voxel.size())};
  VoxelEvidence ev;
  ev.hits.assign(pn.size(), 0);
  ev.normal.assign(pn.size(), Eigen::Vector3f::Zero());
  ev.observing_views.assign(pn.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n_occ, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const auto c = g.Cell(pn.voxel[i]);
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      Eigen::Vector3d sum = Eigen::Vector3d::Zero(), free_dir = Eigen::Vector3d::Zero();
      int count = 0;
      for (int dz = -2; dz <= 2; ++dz)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const int64_t n = Neighbour(g, c, dx, dy, dz);
            if (n < 0) continue;
            const Eigen::Vector3d o(dx, dy, dz);
            const VoxelState st = g.state(size_t(n));
            if (st == VoxelState::kOccupied) s += o * o.transpose(), sum += o, ++count;
            else if (st == VoxelState::kFree && std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1) free_dir += o;
          }
      if (count < 8 || free_dir.squaredNorm() < 0.25) continue;
      const Eigen::Vector3d mean = sum / count;
      const Eigen::Matrix3d cov = s / count - mean * mean.transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
      const Eigen::Vector3d lambda = es.eigenvalues();
      if (!(lambda[0] < options.planar_ratio * lambda[1])) continue;
      Eigen::Vector3d n = es.eigenvectors().col(0);
      const double side = n.dot(free_dir.normalized());
      if (std::abs(side) < 0.5) continue;
      if (side < 0) n = -n;
      ev.normal[i] = n.cast<float>();
      ev.hits[i] = 1;
      ev.observing_views[i] = 1;
    }
  });
  const std::vector<DetectedPlane> planes = DetectPlanes(g, pn, ev, options.planes);
  *planes_found = planes.size();
  *planes_used = 0;
  std::vector<uint16_t> plane_label(node_voxel.size(), 0);
  for (const DetectedPlane& p : planes) {
    std::map<int, size_t> votes;
    for (int m : p.members) ++votes[label_of[pn.voxel[size_t(m)]]];
    int best = 0;
    size_t best_n = 0;
    for (const auto& [l, n] : votes)
      if (l > 0 && n > best_n) best = l, best_n = n;
    if (best == 0) continue;
    bool used = false;
    for (int h : p.hull_nodes)
      if (size_t(h) >= n_occ && plane_label[size_t(h) - n_occ] == 0) plane_label[size_t(h) - n_occ] = uint16_t(best), used = true;
    *planes_used += used;
  }
  *node_of_voxel = std::move(pn.node_of_voxel);
  for (int32_t& v : *node_of_voxel) v = v >= int32_t(n_occ) ? v - int32_t(n_occ) : -1;
  return plane_label;
}

// Phase 4: the completion CRF over the nodes. Labels: empty, the plane labels and the labels of fixed
// occupied voxels next to the nodes; per node its 6 face neighbours (>= 0 node, -1 nothing, -2 free,
// -2 - l the fixed label index l).
struct CompletionProblem {
  std::vector<int> label_value = {0};  // Label index -> NYU40 id (0: empty).
  std::vector<std::array<int32_t, 6>> nb;
  std::vector<float> unary;            // nodes x labels.
  float V(int a, int b, const ObjectRemovalOptions& o) const {
    if (a == b) return 0.f;
    return float(a == 0 || b == 0 ? o.w_occupancy : o.w_semantic);
  }
};
Status SolveCompletion(const VoxelGrid& g, const std::vector<uint16_t>& label_of, const std::vector<uint32_t>& node_voxel,
                       const std::vector<int32_t>& node_of_voxel, const std::vector<uint16_t>& plane_label,
                       const ObjectRemovalOptions& options, CompletionProblem* prob, std::vector<int>* labels,
                       ObjectRemovalResult* out) {
  const int n_nodes = int(node_voxel.size());
  std::vector<int> index_of_label(65536, -1);
  index_of_label[0] = 0;
  auto add_label = [&](int l) {
    if (l > 0 && index_of_label[size_t(l)] < 0) index_of_label[size_t(l)] = int(prob->label_value.size()), prob->label_value.push_back(l);
  };
  prob->nb.assign(size_t(n_nodes), {});
  for (int i = 0; i < n_nodes; ++i) {
    add_label(plane_label[size_t(i)]);
    const auto c = g.Cell(node_voxel[size_t(i)]);
    for (int f = 0; f < 6; ++f) {
      const int64_t n = Neighbour(g, c, kFace6[f][0], kFace6[f][1], kFace6[f][2]);
      int32_t code = -1;
      if (n >= 0) {
        if (node_of_voxel[size_t(n)] >= 0) code = node_of_voxel[size_t(n)];
        else if (g.state(size_t(n)) == VoxelState::kFree) code = -2;
        else if (g.state(size_t(n)) == VoxelState::kOccupied) add_label(label_of[size_t(n)]), code = -2 - index_of_label[label_of[size_t(n)]];
      }
      prob->nb[size_t(i)][size_t(f)] = code;
    }
  }
  const int L = int(prob->label_value.size());
  labels->assign(size_t(n_nodes), 0);
  prob->unary.assign(size_t(n_nodes) * size_t(L), 0.f);
  if (n_nodes == 0) return Status::Ok();
  CrfEnergy energy(n_nodes, L);
  std::vector<float> matrix(size_t(L) * L);
  for (int a = 0; a < L; ++a)
    for (int b = 0; b < L; ++b) matrix[size_t(a) * L + b] = prob->V(a, b, options);
  const int model = L > 1 ? energy.AddCompatibilityModel(matrix) : CrfEnergy::kPottsModel;
  for (int i = 0; i < n_nodes; ++i) {
    float* u = &prob->unary[size_t(i) * L];
    const int pl = plane_label[size_t(i)] ? index_of_label[plane_label[size_t(i)]] : -1;
    for (int k = 0; k < L; ++k) {
      float cost = k ? float(options.w_unseen) : 0.f;
      for (int f = 0; f < 6; ++f) {
        const int32_t code = prob->nb[size_t(i)][size_t(f)];
        // A fixed occupied neighbour only asks for semantic agreement: it does not pull unseen space
        // into occupancy (that would thicken every surface into the unknown space behind it).
        if (code == -2) cost += prob->V(k, 0, options);
        else if (code < -2 && k != 0) cost += prob->V(k, -2 - code, options);
      }
      if (pl >= 0 && k != pl) cost += float(options.w_plane);
      u[k] = cost;
      energy.SetUnary(i, k, cost);
    }
    for (int f = 0; f < 6; f += 2) {  // +x, +y, +z: each edge once.
      const int32_t j = prob->nb[size_t(i)][size_t(f)];
      if (j >= 0) energy.AddEdge(i, j, 1.0f, model);
    }
  }
  std::vector<CrfLabel> x;
  SEMVOX_RETURN_IF_ERROR(InitializeLabels(energy, options.solver.initial_labelling, &x));
  out->energy_initial = energy.Evaluate(x);
  CrfSolverSummary summary;
  SEMVOX_RETURN_IF_ERROR(MinimizeWithAlphaExpansion(energy, options.solver, &x, &summary));
  out->energy_final = energy.Evaluate(x);
  labels->assign(x.begin(), x.end());
  return Status::Ok();
}

// Phase 5: the new map: the remaining records, then a record per node labelled occupied (with its
// confidence p(l_i | neighbours) under the final energy); node states after completion. Returns the indices
// into m->occupied of the completed records.
std::vector<size_t> ApplyCompletion(const SemanticMap& map, const std::vector<uint8_t>& remove, const std::vector<uint32_t>& removed,
                                    const std::vector<uint32_t>& node_voxel, const CompletionProblem& prob, const std::vector<int>& labels,
                                    const ObjectRemovalOptions& options, VoxelGrid* g, SemanticMap* m,
                                    std::vector<std::pair<int, size_t>>* completed_labels_out) {
  const int n_nodes = int(node_voxel.size());
  const int L = int(prob.label_value.size());
  std::vector<uint8_t> is_removed(g->size(), 0);
  for (uint32_t v : removed) is_removed[v] = 1;
  for (size_t k = 0; k < map.occupied.size(); ++k)
    if (!remove[k]) m->occupied.push_back(map.occupied[k]);
  std::vector<size_t> fresh;
  std::map<int, size_t> completed_labels;
  for (int i = 0; i < n_nodes; ++i) {
    const uint32_t v = node_voxel[size_t(i)];
    const int k = labels[size_t(i)];
    if (k == 0) {
      g->set_state(v, is_removed[v] ? VoxelState::kFree : VoxelState::kUnknown);
      continue;
    }
    g->set_state(v, VoxelState::kOccupied);
    std::vector<double> e(static_cast<size_t>(L), 0.0);
    double e_min = 1e300;
    for (int l = 0; l < L; ++l) {
      double s = prob.unary[size_t(i) * L + size_t(l)];
      for (int f = 0; f < 6; ++f) {
        const int32_t j = prob.nb[size_t(i)][size_t(f)];
        if (j >= 0) s += prob.V(l, labels[size_t(j)], options);
      }
      e[size_t(l)] = s, e_min = std::min(e_min, s);
    }
    double z = 0;
    for (double s : e) z += std::exp(-(s - e_min));
    SemanticVoxelRecord r;
    r.voxel = v;
    const auto c = g->Cell(v);
    r.centre = g->CellCenter(c[0], c[1], c[2]).cast<float>();
    r.label = uint16_t(prob.label_value[size_t(k)]);
    r.confidence = float(std::exp(-(e[size_t(k)] - e_min)) / z);
    r.completed = 1;
    fresh.push_back(m->occupied.size());
    m->occupied.push_back(r);
    ++completed_labels[r.label];
  }
  completed_labels_out->assign(completed_labels.begin(), completed_labels.end());
  return fresh;
}

// Phase 6: colours (and rooms) of the completed records from their coloured 26-neighbours of the same
// label, grown outwards; records connected to none take their label's mean colour (or its NYU40 colour).
void ColourCompleted(const VoxelGrid& g, const std::vector<size_t>& fresh, SemanticMap* map) {
  SemanticMap& m = *map;
  std::vector<int32_t> rec(g.size(), -1);
  for (size_t k = 0; k < m.occupied.size(); ++k) rec[m.occupied[k].voxel] = int32_t(k);
  std::vector<uint8_t> coloured(m.occupied.size(), 1);
  for (size_t k : fresh) coloured[k] = 0;
  std::vector<size_t> pending = fresh;
  while (!pending.empty()) {
    struct Paint { size_t k; std::array<uint8_t, 3> rgb; int32_t room; };
    std::vector<Paint> paint;
    std::vector<size_t> still;
    for (size_t k : pending) {
      const auto& r = m.occupied[k];
      const auto c = g.Cell(r.voxel);
      double sum[3] = {0, 0, 0};
      int n = 0;
      int32_t room = -1;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int64_t q = Neighbour(g, c, dx, dy, dz);
            if (q < 0 || rec[size_t(q)] < 0) continue;
            const auto& o = m.occupied[size_t(rec[size_t(q)])];
            if (!coloured[size_t(rec[size_t(q)])] || o.label != r.label) continue;
            for (int ch = 0; ch < 3; ++ch) sum[ch] += o.rgb[size_t(ch)];
            if (n++ == 0) room = o.room;
          }
      if (n == 0) {
        still.push_back(k);
        continue;
      }
      paint.push_back({k, {uint8_t(std::lround(sum[0] / n)), uint8_t(std::lround(sum[1] / n)), uint8_t(std::lround(sum[2] / n))}, room});
    }
    if (paint.empty()) break;
    for (const Paint& p : paint) m.occupied[p.k].rgb = p.rgb, m.occupied[p.k].room = p.room, coloured[p.k] = 1;
    pending.swap(still);
  }
  if (pending.empty()) return;
  // Not connected to a coloured voxel of their label: the label's mean colour.
  std::map<int, std::array<double, 4>> mean;
  for (size_t k = 0; k < m.occupied.size(); ++k)
    if (coloured[k]) {
      auto& a = mean[m.occupied[k].label];
      for (int ch = 0; ch < 3; ++ch) a[size_t(ch)] += m.occupied[k].rgb[size_t(ch)];
      a[3] += 1;
    }
  for (size_t k : pending) {
    auto& r = m.occupied[k];
    auto it = mean.find(r.label);
    if (it != mean.end() && it->second[3] > 0) {
      for (int ch = 0; ch < 3; ++ch) r.rgb[size_t(ch)] = uint8_t(std::lround(it->second[size_t(ch)] / it->second[3]));
    } else if (r.label < kNumNyu40) {
      const Rgb8 col = Nyu40Labels()[r.label].color;
      r.rgb = {col.r, col.g, col.b};
    }
  }
}

}  // namespace

Status RemoveObjects(const VoxelGrid& grid, const SemanticMap& map, const std::vector<uint8_t>& remove,
                     const ObjectRemovalOptions& options, ObjectRemovalResult* result) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string err;
  if (!options.Check(&err)) return Status::InvalidInput("object removal options: " + err);
  if (remove.size() != map.occupied.size()) return Status::Internal("RemoveObjects: one flag per record expected");
  ObjectRemovalResult& out = *result;
  out = ObjectRemovalResult{};
  VoxelGrid g = grid;
  const AfterRemoval after = ClearRemoved(map, remove, &g);
  out.removed_voxels = after.removed.size();
  const int band = int(std::floor(options.completion_band_m / g.resolution() + 1e-9));
  const std::vector<uint32_t> node_voxel = CompletionNodes(g, after.removed, band);
  out.nodes = node_voxel.size();
  out.unknown_nodes = node_voxel.size() - after.removed.size();
  std::vector<int32_t> node_of_voxel;
  const std::vector<uint16_t> plane_label =
      PlaneLabelsOfNodes(g, after.label_of, node_voxel, options, &node_of_voxel, &out.planes, &out.planes_used);
  CompletionProblem prob;
  std::vector<int> labels;
  SEMVOX_RETURN_IF_ERROR(SolveCompletion(g, after.label_of, node_voxel, node_of_voxel, plane_label, options, &prob, &labels, &out));
  const std::vector<size_t> fresh =
      ApplyCompletion(map, remove, after.removed, node_voxel, prob, labels, options, &g, &out.map, &out.completed_labels);
  out.completed_voxels = fresh.size();
  ColourCompleted(g, fresh, &out.map);
  SemanticMap& m = out.map;
  std::sort(m.occupied.begin(), m.occupied.end(), [](const SemanticVoxelRecord& a, const SemanticVoxelRecord& b) { return a.voxel < b.voxel; });
  m.node_occupied.clear();
  out.grid = std::move(g);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return Status::Ok();
}

Status WriteVoxelMesh(const VoxelGrid& grid, const SemanticMap& map, const std::string& ply_path,
                      const std::string& obj_path, VoxelMeshStats* stats, const Eigen::Isometry3d& input_from_world) {
  // Corners of each face, counter-clockwise seen from outside (normal = the face direction kFace6[f]).
  static constexpr int kCorners[6][4][3] = {
      {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}};
  const auto& d = grid.dims();
  const uint64_t sx = uint64_t(d[0]) + 1, sy = uint64_t(d[1]) + 1;
  std::unordered_map<uint64_t, uint32_t> vertex_of_corner;
  std::vector<Eigen::Vector3d> vertices;
  struct Quad { std::array<uint32_t, 4> v; size_t record; };
  std::vector<Quad> quads;
  const Eigen::Vector3d lo = grid.MinCorner();
  const double res = grid.resolution();
  for (size_t k = 0; k < map.occupied.size(); ++k) {
    const auto c = grid.Cell(map.occupied[k].voxel);
    for (int f = 0; f < 6; ++f) {
      const int64_t n = Neighbour(grid, c, kFace6[f][0], kFace6[f][1], kFace6[f][2]);
      if (n >= 0 && grid.state(size_t(n)) == VoxelState::kOccupied) continue;
      Quad q{{}, k};
      for (int j = 0; j < 4; ++j) {
        const uint64_t x = uint64_t(c[0] + kCorners[f][j][0]), y = uint64_t(c[1] + kCorners[f][j][1]), z = uint64_t(c[2] + kCorners[f][j][2]);
        const auto [it, inserted] = vertex_of_corner.try_emplace((z * sy + y) * sx + x, uint32_t(vertices.size()));
        if (inserted) vertices.push_back(lo + res * Eigen::Vector3d(double(x), double(y), double(z)));
        q.v[size_t(j)] = it->second;
      }
      quads.push_back(q);
    }
  }
  if (stats) stats->vertices = vertices.size(), stats->quads = quads.size();
  if (!IsIdentity(input_from_world))
    for (Eigen::Vector3d& v : vertices) v = input_from_world * v;

  // PLY: two triangles per quad, per-face colour and label.
  {
    const size_t nv = vertices.size(), nf = 2 * quads.size();
    std::vector<double> x(nv), y(nv), z(nv);
    for (size_t i = 0; i < nv; ++i) x[i] = vertices[i].x(), y[i] = vertices[i].y(), z[i] = vertices[i].z();
    std::vector<double> idx, red(nf), green(nf), blue(nf), label(nf);
    idx.reserve(3 * nf);
    for (size_t q = 0; q < quads.size(); ++q) {
      const auto& v = quads[q].v;
      idx.insert(idx.end(), {double(v[0]), double(v[1]), double(v[2]), double(v[0]), double(v[2]), double(v[3])});
      const auto& r = map.occupied[quads[q].record];
      for (size_t t = 2 * q; t < 2 * q + 2; ++t) red[t] = r.rgb[0], green[t] = r.rgb[1], blue[t] = r.rgb[2], label[t] = r.label;
    }
    PlyWriter w;
    w.AddComment("semvox mesh.ply: boundary faces of the occupied voxels; face label = NYU40 id (docs/outputs.md)");
    w.AddElement("vertex", nv);
    w.AddProperty("x", PlyType::kFloat32, std::move(x));
    w.AddProperty("y", PlyType::kFloat32, std::move(y));
    w.AddProperty("z", PlyType::kFloat32, std::move(z));
    w.AddElement("face", nf);
    w.AddListProperty("vertex_indices", PlyType::kUInt8, PlyType::kInt32, 3, std::move(idx));
    w.AddProperty("red", PlyType::kUInt8, std::move(red));
    w.AddProperty("green", PlyType::kUInt8, std::move(green));
    w.AddProperty("blue", PlyType::kUInt8, std::move(blue));
    w.AddProperty("label", PlyType::kUInt16, std::move(label));
    SEMVOX_RETURN_IF_ERROR(w.Write(ply_path));
  }

  // OBJ + MTL: quads grouped by label, one material per label (Kd = the label's mean colour).
  std::map<int, std::vector<size_t>> quads_of_label;
  std::map<int, std::array<double, 4>> colour_sum;
  for (size_t q = 0; q < quads.size(); ++q) quads_of_label[map.occupied[quads[q].record].label].push_back(q);
  for (const auto& r : map.occupied) {
    auto& a = colour_sum[r.label];
    a[0] += r.rgb[0], a[1] += r.rgb[1], a[2] += r.rgb[2], a[3] += 1;
  }
  auto material = [](int label) {
    std::string name = label > 0 && label < kNumNyu40 ? Nyu40Labels()[size_t(label)].name : "unlabelled";
    std::replace(name.begin(), name.end(), ' ', '_');
    return "label_" + std::to_string(label) + "_" + name;
  };
  std::string mtl_name = obj_path.substr(obj_path.find_last_of('/') + 1);
  mtl_name = mtl_name.substr(0, mtl_name.rfind('.')) + ".mtl";
  const std::string mtl_path = obj_path.substr(0, obj_path.find_last_of('/') + 1) + mtl_name;
  std::string mtl = "# semvox mesh.mtl: one material per NYU40 label (Kd = mean voxel colour of the label)\n";
  char buf[160];
  for (const auto& [label, a] : colour_sum) {
    if (!quads_of_label.count(label)) continue;
    std::snprintf(buf, sizeof(buf), "newmtl %s\nKa 0 0 0\nKd %.4f %.4f %.4f\nKs 0 0 0\nd 1\nillum 1\n\n", material(label).c_str(),
                  a[0] / a[3] / 255.0, a[1] / a[3] / 255.0, a[2] / a[3] / 255.0);
    mtl += buf;
  }
  std::string obj;
  obj.reserve(vertices.size() * 32 + quads.size() * 40);
  obj += "# semvox mesh.obj: boundary faces of the occupied voxels, grouped by NYU40 label (docs/outputs.md)\n";
  obj += "mtllib " + mtl_name + "\n";
  for (const auto& v : vertices) {
    std::snprintf(buf, sizeof(buf), "v %.4f %.4f %.4f\n", v.x(), v.y(), v.z());
    obj += buf;
  }
  for (const auto& [label, qs] : quads_of_label) {
    obj += "g " + material(label) + "\nusemtl " + material(label) + "\n";
    for (size_t q : qs) {
      const auto& v = quads[q].v;
      std::snprintf(buf, sizeof(buf), "f %u %u %u %u\n", v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1);
      obj += buf;
    }
  }
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic(mtl_path, mtl));
  return WriteFileAtomic(obj_path, obj);
}

}  // namespace semvox
