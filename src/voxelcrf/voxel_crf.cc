#include "voxelcrf/voxel_crf.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/file_util.h"
#include "core/hash.h"
#include "core/labels.h"
#include "core/log.h"
#include "mapping/ray_traversal.h"

namespace semvox {

namespace {

constexpr float kMinProbability = 1e-3f;
float NegLog(float p) { return -std::log(std::max(p, kMinProbability)); }

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

// Colour-difference clusters of visible pairs (RGB distance, 0-255 per channel).
int ColourCluster(const std::array<uint8_t, 3>& a, const std::array<uint8_t, 3>& b) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (double(a[size_t(k)]) - b[size_t(k)]) * (double(a[size_t(k)]) - b[size_t(k)]);
  return d2 < 15.0 * 15.0 ? 0 : d2 < 45.0 * 45.0 ? 1 : 2;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Layout prior and model file.

int LayoutPrior::HeightBin(double z, double floor_z, double ceiling_z) {
  const int half = kHeightBins / 2;
  const double mid = 0.5 * (floor_z + ceiling_z);
  if (z < mid) return std::clamp(int(std::floor((z - floor_z) / 0.1)), 0, half - 1);
  return half + std::clamp(int(std::floor((ceiling_z - z) / 0.1)), 0, half - 1);
}

int LayoutPrior::NormalBin(const Eigen::Vector3f& n) {
  if (n.squaredNorm() < 0.25f) return 0;
  if (n.z() > 0.7f) return 1;
  if (n.z() < -0.7f) return 2;
  return 3;
}

LayoutPrior LayoutPrior::FromCounts(int num_classes, const std::vector<double>& counts) {
  LayoutPrior p;
  p.num_classes = num_classes;
  p.counts = counts;
  p.neg_log_p.assign(counts.size(), 0.f);
  const size_t cells = counts.size() / size_t(num_classes);
  for (size_t c = 0; c < cells; ++c) {
    double total = 0;
    for (int k = 0; k < num_classes; ++k) total += counts[c * size_t(num_classes) + size_t(k)] + 1.0;
    for (int k = 0; k < num_classes; ++k)
      p.neg_log_p[c * size_t(num_classes) + size_t(k)] = float(-std::log((counts[c * size_t(num_classes) + size_t(k)] + 1.0) / total));
  }
  return p;
}

bool LayoutPrior::RecoverCounts() {
  counts.clear();
  const size_t K = size_t(num_classes);
  if (K == 0 || neg_log_p.empty() || neg_log_p.size() % K) return false;
  std::vector<double> n(neg_log_p.size(), 0.0);
  for (size_t c = 0; c < neg_log_p.size() / K; ++c) {
    const float* row = &neg_log_p[c * K];
    const float lo = *std::min_element(row, row + K), hi = *std::max_element(row, row + K);
    if (hi - lo < 1e-6f) continue;  // A uniform cell: no voxel was counted there (or as many of each class).
    const double total = std::exp(double(hi));  // n + K = 1 / min_k p.
    for (size_t k = 0; k < K; ++k) {
      const double v = std::exp(-double(row[k])) * total - 1.0;
      if (std::fabs(v - std::round(v)) > 0.05 || std::round(v) < 0) return false;
      n[c * K + k] = std::round(v);
    }
    // The cell's smallest count must be 0, else 1 / min_k p is not n + K.
    if (*std::min_element(n.begin() + std::ptrdiff_t(c * K), n.begin() + std::ptrdiff_t((c + 1) * K)) != 0) return false;
  }
  counts = std::move(n);
  return true;
}

std::vector<float> LayoutPrior::RatioCosts(double pseudo_count, double power) const {
  const size_t K = size_t(num_classes);
  if (K == 0 || counts.size() != neg_log_p.size() || counts.empty()) return {};
  const size_t cells = counts.size() / K;
  std::vector<double> share(K, 0.0);
  double all = 0;
  for (size_t i = 0; i < counts.size(); ++i) share[i % K] += counts[i], all += counts[i];
  if (all <= 0) return {};
  for (double& v : share) v = std::max(v / all, 1e-6);
  std::vector<float> out(counts.size());
  std::vector<double> r(K);
  for (size_t c = 0; c < cells; ++c) {
    double n = 0;
    for (size_t k = 0; k < K; ++k) n += counts[c * K + k];
    double lo = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < K; ++k) {
      const double p = (counts[c * K + k] + pseudo_count * share[k]) / std::max(n + pseudo_count, 1e-12);
      r[k] = -std::log(std::max(p, 1e-12)) + power * std::log(share[k]);
      lo = std::min(lo, r[k]);
    }
    const float* row = &neg_log_p[c * K];
    const double keep = *std::min_element(row, row + K);
    for (size_t k = 0; k < K; ++k) out[c * K + k] = float(r[k] - lo + keep);
  }
  return out;
}

VoxelCrfModel VoxelCrfModel::Default(std::vector<int> nyu40_of_class, std::vector<std::string> class_names) {
  VoxelCrfModel m;
  m.nyu40_of_class = std::move(nyu40_of_class);
  m.class_names = std::move(class_names);
  m.w[kWAppearance] = 1.0;
  m.w[kWDepthOccupied] = 0.3;
  m.w[kWDensityOccupied] = 0.5;
  m.w[kWDepthEmpty] = 0.3;
  m.w[kWDensityEmpty] = 0.5;
  m.w[kWUnseenOccupied] = 1.0;
  m.w[kWMapOccupiedEmpty] = 2.0;
  m.w[kWMapFreeOccupied] = 2.0;
  m.w[kWOccupiedBias] = 0.0;
  m.w[kWLayout] = 0.3;
  for (int t = 0; t < 10; ++t) m.w[size_t(kWPairwise3d + t)] = (t % 5 == 0) ? 0.6 : (t % 5 == 1) ? 0.4 : (t % 5 == 2) ? 0.2 : 0.4;
  m.w[kWPairwise2d] = 0.2;
  m.w[kWPlane] = 2.0;
  m.w[kWObject] = 0.5;
  m.w[kWSegment] = 1.0;
  return m;
}

Status VoxelCrfModel::Save(const std::string& path) const {
  std::ostringstream os;
  os.precision(9);
  os << "# semvox Voxel-CRF model (voxelcrf/voxel_crf.h): weights, classes (index nyu40 name), layout prior\n";
  os << "weights " << kNumVoxelCrfWeights;
  for (double v : w) os << ' ' << v;
  os << "\nclasses " << num_classes() << '\n';
  for (int k = 0; k < num_classes(); ++k) os << k << ' ' << nyu40_of_class[size_t(k)] << ' ' << class_names[size_t(k)] << '\n';
  auto table = [&](const char* name, const auto& values) {  // One cell (K values) per line.
    os << name << ' ' << values.size() << '\n';
    for (size_t i = 0; i < values.size(); ++i) os << values[i] << ((i + 1) % size_t(std::max(1, num_classes())) ? ' ' : '\n');
  };
  table("layout", layout.neg_log_p);
  if (!layout.counts.empty() && layout.counts.size() == layout.neg_log_p.size()) table("layout_counts", layout.counts);
  return WriteFileAtomic(path, os.str());
}

Result<VoxelCrfModel> VoxelCrfModel::Load(const std::string& path) {
  std::string bytes;
  SEMVOX_RETURN_IF_ERROR(ReadFileBytes(path, &bytes));
  std::istringstream is(bytes);
  auto bad = [&](const std::string& what) {
    return Status::InvalidInput(FileError(path, what, "re-create it with `semvox train`"));
  };
  std::string line, word;
  VoxelCrfModel m;
  while (std::getline(is, line) && (line.empty() || line[0] == '#')) {
  }
  std::istringstream ws(line);
  int n = 0;
  // Models written before the object-segment term have one weight fewer; it is 0 for them.
  if (!(ws >> word >> n) || word != "weights" || (n != kNumVoxelCrfWeights && n != kWSegment))
    return bad("expected 'weights " + std::to_string(kNumVoxelCrfWeights) + " ...' first");
  for (int i = 0; i < n; ++i)
    if (!(ws >> m.w[size_t(i)]) || !std::isfinite(m.w[size_t(i)])) return bad("a weight is missing or not a number");
  int k = 0;
  if (!(is >> word >> k) || word != "classes" || k < 1 || k > 1000) return bad("expected 'classes K'");
  for (int c = 0; c < k; ++c) {
    int idx = 0, id = 0;
    std::string name;
    if (!(is >> idx >> id) || idx != c || id < 0 || id >= kNumNyu40 || !std::getline(is, name)) return bad("bad class line " + std::to_string(c));
    name.erase(0, name.find_first_not_of(' '));  // Names may hold spaces ("shower curtain").
    if (name.empty()) return bad("class line " + std::to_string(c) + " has no name");
    m.nyu40_of_class.push_back(id);
    m.class_names.push_back(name);
  }
  size_t cells = 0;
  if (!(is >> word >> cells) || word != "layout") return bad("expected 'layout N'");
  if (cells != 0 && cells != size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * size_t(k))
    return bad("layout prior has " + std::to_string(cells) + " values, expected 0 or " +
               std::to_string(LayoutPrior::kHeightBins * LayoutPrior::kNormalBins * k));
  m.layout.num_classes = k;
  m.layout.neg_log_p.resize(cells);
  for (float& v : m.layout.neg_log_p)
    if (!(is >> v) || !std::isfinite(v)) return bad("layout prior value missing or not a number");
  size_t counted = 0;
  if (is >> word) {
    if (word != "layout_counts" || !(is >> counted) || counted != cells) return bad("expected 'layout_counts " + std::to_string(cells) + "' after the layout prior");
    m.layout.counts.resize(counted);
    for (double& v : m.layout.counts)
      if (!(is >> v) || !std::isfinite(v) || v < 0) return bad("layout count missing, negative or not a number");
  } else {
    m.layout.RecoverCounts();  // Older files; without counts the ratio form falls back to the frequency form.
  }
  return m;
}

bool VoxelCrfOptions::Check(std::string* error) const {
  return CheckOptions(*this, Options(), error) && planes.Check(error) && solver.Check(error);
}

// ---------------------------------------------------------------------------------------------------------
// Visibility (Eq. 9).

namespace {

// Calls walk(k, ray, origin, end, traverse) for every ray k of `ev`, in parallel (TBB); traverse(from, end,
// visitor) is TraverseGrid over `grid`.
template <typename Walk>
void ForEachRay(const VoxelGrid& grid, const VoxelEvidence& ev, Walk&& walk) {
  const int okey[3] = {grid.origin_key()[0], grid.origin_key()[1], grid.origin_key()[2]};
  const int dims[3] = {grid.dims()[0], grid.dims()[1], grid.dims()[2]};
  auto traverse = [&](const Eigen::Vector3f& from, const Eigen::Vector3f& end, auto&& visit) {
    TraverseGrid<false>(from, end, grid.resolution(), okey, dims, visit);
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, ev.rays.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const EvidenceRay& ray = ev.rays[k];
      const Eigen::Vector3f& o = ev.origins[size_t(ray.origin)];
      walk(k, ray, o, Eigen::Vector3f(o + ray.direction * ray.max_t), traverse);
    }
  });
}

}  // namespace

std::vector<int32_t> ComputeVisibility(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev,
                                       const std::vector<int>& labels, const std::vector<float>* starts) {
  std::vector<int32_t> out(ev.rays.size(), -1);
  ForEachRay(grid, ev, [&](size_t k, const EvidenceRay& ray, const Eigen::Vector3f& o, const Eigen::Vector3f& end, auto&& traverse) {
    Eigen::Vector3f from = o;
    if (starts) {
      const float t = (*starts)[k];
      if (t < 0) return;  // Blocked (or out of the grid) before any node: -1 for every labelling.
      from = o + ray.direction * t;
    }
    int32_t found = -1;
    traverse(from, end, [&](size_t idx) {
      const int32_t node = nodes.node_of_voxel[idx];
      if (node >= 0) {
        if (labels[size_t(node)] != 0) {
          found = node;
          return false;
        }
        return true;
      }
      return grid.state(idx) != VoxelState::kOccupied;  // An occupied voxel outside the CRF blocks the ray.
    });
    out[k] = found;
  });
  return out;
}

std::vector<float> ComputeRayStarts(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev) {
  // Most of a ray's way from its camera to its first node is free space far from any node: the grid is cut
  // into kB^3 blocks, and a block without a node or an occupied voxel is crossed in one step (its exit along
  // the ray, by the slab test). The cell-by-cell walk (TraverseGrid, as before) starts at the first block that
  // holds either, backed up by 1.5 voxels into the empty blocks crossed, so that the cell before the first
  // node is always walked: the start is the midpoint of that cell's stretch of the ray, as in the plain walk.
  constexpr int kB = 4;
  const double res = grid.resolution();
  const auto dims = grid.dims();
  const int nb[3] = {(dims[0] + kB - 1) / kB, (dims[1] + kB - 1) / kB, (dims[2] + kB - 1) / kB};
  std::vector<uint8_t> busy(size_t(nb[0]) * size_t(nb[1]) * size_t(nb[2]), 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, nb[2]), [&](const tbb::blocked_range<int>& r) {
    for (int bz = r.begin(); bz != r.end(); ++bz)
      for (int z = bz * kB; z < std::min(dims[2], (bz + 1) * kB); ++z)
        for (int y = 0; y < dims[1]; ++y)
          for (int x = 0; x < dims[0]; ++x) {
            const size_t idx = grid.Index(x, y, z);
            if (nodes.node_of_voxel[idx] >= 0 || grid.state(idx) == VoxelState::kOccupied)
              busy[(size_t(bz) * size_t(nb[1]) + size_t(y / kB)) * size_t(nb[0]) + size_t(x / kB)] = 1;
          }
  });
  const double inv = 1.0 / res;
  const int64_t okey[3] = {grid.origin_key()[0], grid.origin_key()[1], grid.origin_key()[2]};
  std::vector<float> out(ev.rays.size(), -1.f);
  ForEachRay(grid, ev, [&](size_t k, const EvidenceRay& ray, const Eigen::Vector3f& o, const Eigen::Vector3f& end, auto&& traverse) {
    const float length = ray.max_t;
    const Eigen::Vector3f& dir = ray.direction;
    // Skip empty blocks: t_skip is where the cell walk begins (0 or inside the empty blocks crossed).
    float t = 0.f, t_skip = 0.f;
    for (;;) {
      const Eigen::Vector3f p = o + dir * t;
      int64_t c[3];
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        c[a] = int64_t(std::floor(double(p[a]) * inv)) + kKeyOffset - okey[a];
        inside &= c[a] >= 0 && c[a] < dims[size_t(a)];
      }
      if (!inside) {
        if (t == 0.f) return;  // The camera is outside the grid: no node, as the plain walk finds.
        break;                 // Left the grid through empty blocks: the walk below finds nothing either.
      }
      const int64_t b[3] = {c[0] / kB, c[1] / kB, c[2] / kB};
      if (busy[(size_t(b[2]) * size_t(nb[1]) + size_t(b[1])) * size_t(nb[0]) + size_t(b[0])]) break;
      float exit = std::numeric_limits<float>::infinity();
      for (int a = 0; a < 3; ++a) {
        if (dir[a] == 0.f) continue;
        const int64_t face = dir[a] > 0 ? std::min<int64_t>((b[a] + 1) * kB, dims[size_t(a)]) : b[a] * kB;
        const double wall = double(face + okey[a] - kKeyOffset) * res;
        exit = std::min(exit, float((wall - double(o[a])) / double(dir[a])));
      }
      const float next = std::max(exit, t) + float(1e-3 * res);
      if (next >= length) return;  // The segment ends in empty blocks: no node.
      t_skip = std::max(t_skip, t);  // t lies in an empty block.
      t = next;
    }
    // Back into the empty blocks by 1.5 voxels (no further than the last point known to lie in one).
    const float t0 = std::max(t_skip, t - float(1.5 * res));
    double previous = -1;  // Entry distance of the cell before the current one.
    float start = -1.f;
    traverse(Eigen::Vector3f(o + dir * t0), end, [&](size_t idx, double tc) {
      if (nodes.node_of_voxel[idx] >= 0) {
        start = previous < 0 ? t0 : float(t0 + 0.5 * (previous + tc));
        return false;
      }
      if (grid.state(idx) == VoxelState::kOccupied) return false;
      previous = tc;
      return true;
    });
    out[k] = start;
  });
  return out;
}

// ---------------------------------------------------------------------------------------------------------
// Problem construction.

namespace {
// Fixed node ranges of the problem's per-node passes (the result does not depend on the thread count).
constexpr int kBuildParts = 2;
}  // namespace

VoxelCrfProblem BuildVoxelCrfProblem(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev,
                                     double floor_z, double ceiling_z, const VoxelCrfModel& model,
                                     const std::vector<DetectedPlane>& planes, const VoxelCrfOptions& options,
                                     const std::vector<int32_t>& visible_node_of_ray) {
  const int n = int(nodes.size());
  const int K = ev.num_classes;
  VoxelCrfProblem p;
  p.num_nodes = n;
  p.num_labels = K + 1;
  // Appearance: mean class distribution of the rays each node is visible in. kBuildParts fixed node ranges
  // in parallel, each walking all rays in order and summing only its own nodes' (so every node sums its rays
  // in ray order, as one pass over the rays does).
  std::vector<float> app(size_t(n) * K, 0.f);
  std::vector<int> count(size_t(n), 0);
  tbb::parallel_for(0, kBuildParts, [&](int part) {
    const int32_t lo = int32_t(int64_t(n) * part / kBuildParts), hi = int32_t(int64_t(n) * (part + 1) / kBuildParts);
    for (size_t r = 0; r < ev.rays.size(); ++r) {
      const int32_t node = visible_node_of_ray[r];
      if (node < lo || node >= hi) continue;  // Also skips -1 (not visible).
      const float* o = &ev.observations[size_t(ev.rays[r].observation) * K];
      float* a = &app[size_t(node) * K];
      for (int k = 0; k < K; ++k) a[k] += o[k];
      ++count[size_t(node)];
    }
  });
  p.f_appearance.assign(size_t(n) * K, 0.f);
  p.f_layout.assign(size_t(n) * K, 0.f);
  if (ev.segment.size() == size_t(n) * K) {
    p.f_segment.assign(size_t(n) * K, 0.f);
    for (size_t s = 0; s < size_t(n); ++s) {
      const float* q = &ev.segment[s * K];
      if (std::all_of(q, q + K, [](float v) { return v == 0.f; })) continue;
      for (int k = 0; k < K; ++k) p.f_segment[s * K + k] = NegLog(q[k]);
    }
  }
  p.f_depth_empty.assign(size_t(n), 0.f);
  p.f_density_empty.assign(size_t(n), 0.f);
  p.f_depth_occ.assign(size_t(n), 0.f);
  p.f_density_occ.assign(size_t(n), 0.f);
  p.state = nodes.initial_state;
  if (options.keep_scan_points && nodes.holds_point.size() == size_t(n)) p.keep_occupied = nodes.holds_point;
  std::vector<uint8_t> visible(size_t(n), 0);
  const bool have_layout = !model.layout.neg_log_p.empty() && model.layout.num_classes == K;
  // The prior divided by a power of the class frequencies (VoxelCrfOptions::layout_frequency_power) when the
  // model trusts the per-view classifiers; on every node, hidden ones too: their labels come from their
  // visible neighbours' posteriors through the pairwise terms, and the learned prior would pull them back to wall.
  const std::vector<float> ratio =
      have_layout && options.layout_frequency_power > 0 && model.w[kWAppearance] >= VoxelCrfOptions::kEvidenceWeight
          ? model.layout.RatioCosts(options.layout_pseudo_count, options.layout_frequency_power)
          : std::vector<float>{};
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& r) {
    for (int i = r.begin(); i != r.end(); ++i) {
      const size_t s = size_t(i);
      if (count[s] > 0) {
        visible[s] = 1;
        for (int k = 0; k < K; ++k) p.f_appearance[s * K + k] = NegLog(app[s * K + k] / float(count[s]));
      }
      if (ev.observed(s)) {
        const float F = ev.depth_agreement[s], rho = ev.density[s];
        p.f_depth_occ[s] = NegLog(F);
        p.f_depth_empty[s] = NegLog(1.f - F);
        if (ev.reaching_rays[s] > 0) {
          p.f_density_occ[s] = NegLog(rho);
          p.f_density_empty[s] = NegLog(1.f - rho);
        }
      }
      if (have_layout) {
        const auto c = grid.Cell(nodes.voxel[s]);
        const int hb = LayoutPrior::HeightBin(grid.CellCenter(c[0], c[1], c[2]).z(), floor_z, ceiling_z);
        const int nb = LayoutPrior::NormalBin(ev.normal[s]);
        const float* row = ratio.empty() ? nullptr : &ratio[(size_t(hb) * LayoutPrior::kNormalBins + size_t(nb)) * size_t(K)];
        for (int k = 0; k < K; ++k) p.f_layout[s * K + k] = row ? row[k] : model.layout.Cost(hb, nb, k);
      }
    }
  });
  if (options.use_pairwise) {
    // 3D: 6-adjacent pairs (each once: +x, +y, +z), node by node in kBuildParts fixed node ranges in
    // parallel, joined in range order.
    const auto& d = grid.dims();
    const int64_t stride[3] = {1, d[0], int64_t(d[0]) * d[1]};
    std::array<std::vector<VoxelCrfProblem::Edge>, kBuildParts> part_edges;
    tbb::parallel_for(0, kBuildParts, [&](int part) {
      std::vector<VoxelCrfProblem::Edge>& out = part_edges[size_t(part)];
      const int lo = int(int64_t(n) * part / kBuildParts), hi = int(int64_t(n) * (part + 1) / kBuildParts);
      out.reserve(size_t(hi - lo) * 3);
      for (int i = lo; i < hi; ++i) {
        const auto c = grid.Cell(nodes.voxel[size_t(i)]);
        for (int a = 0; a < 3; ++a) {
          if (c[size_t(a)] + 1 >= d[size_t(a)]) continue;
          const int32_t j = nodes.node_of_voxel[size_t(int64_t(nodes.voxel[size_t(i)]) + stride[a])];
          if (j < 0) continue;
          int kase;
          if (visible[size_t(i)] && visible[size_t(j)])
            kase = (ev.hits[size_t(i)] && ev.hits[size_t(j)]) ? ColourCluster(ev.colour[size_t(i)], ev.colour[size_t(j)]) : 1;
          else if (visible[size_t(i)] || visible[size_t(j)])
            kase = 3;
          else
            kase = 4;
          out.push_back({i, j, int16_t(kWPairwise3d + (a == 2 ? 0 : 5) + kase)});
        }
      }
    });
    size_t num_3d = 0;
    for (const auto& e : part_edges) num_3d += e.size();
    p.edges.reserve(num_3d);
    for (const auto& e : part_edges) p.edges.insert(p.edges.end(), e.begin(), e.end());
    // 2D: visible voxels of neighbouring rays of one view, close in 3D but not 6-adjacent. Views in parallel,
    // their pairs joined in view order, then sorted (equal pairs are equal values: any sort gives one order).
    std::vector<std::pair<size_t, size_t>> view_rays;  // [first, end) ray of each view.
    for (size_t r0 = 0; r0 < ev.rays.size();) {
      size_t r1 = r0;
      while (r1 < ev.rays.size() && ev.rays[r1].view == ev.rays[r0].view) ++r1;
      view_rays.emplace_back(r0, r1);
      r0 = r1;
    }
    std::vector<std::vector<std::pair<int, int>>> view_pairs(view_rays.size());
    const double max_d2 = std::pow(2.5 * grid.resolution(), 2);
    tbb::parallel_for(size_t(0), view_rays.size(), [&](size_t v) {
      const auto [r0, r1] = view_rays[v];
      std::vector<std::pair<int, int>>& pairs = view_pairs[v];
      int w = 0, h = 0;
      for (size_t r = r0; r < r1; ++r) {
        w = std::max(w, ev.rays[r].px + 1);
        h = std::max(h, ev.rays[r].py + 1);
      }
      std::vector<int32_t> img(size_t(w) * h, -1);
      for (size_t r = r0; r < r1; ++r) img[size_t(ev.rays[r].py) * w + ev.rays[r].px] = visible_node_of_ray[r];
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int32_t a = img[size_t(y) * w + x];
          if (a < 0) continue;
          for (int k = 0; k < 2; ++k) {
            const int xx = x + (k == 0), yy = y + (k == 1);
            if (xx >= w || yy >= h) continue;
            const int32_t b = img[size_t(yy) * w + xx];
            if (b < 0 || b == a) continue;
            const auto ca = grid.Cell(nodes.voxel[size_t(a)]), cb = grid.Cell(nodes.voxel[size_t(b)]);
            const int dx = ca[0] - cb[0], dy = ca[1] - cb[1], dz = ca[2] - cb[2];
            const int manhattan = std::abs(dx) + std::abs(dy) + std::abs(dz);
            if (manhattan <= 1) continue;  // Same or 6-adjacent: already a 3D edge.
            if (double(dx * dx + dy * dy + dz * dz) * grid.resolution() * grid.resolution() > max_d2) continue;
            pairs.emplace_back(std::min(a, b), std::max(a, b));
          }
        }
    });
    std::vector<std::pair<int, int>> pairs;
    for (const auto& vp : view_pairs) pairs.insert(pairs.end(), vp.begin(), vp.end());
    view_pairs.clear();
    tbb::parallel_sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    p.edges.reserve(p.edges.size() + pairs.size());
    for (const auto& [a, b] : pairs) p.edges.push_back({a, b, int16_t(kWPairwise2d)});
  }
  if (options.use_higher_order) {
    for (const DetectedPlane& plane : planes) {
      if (plane.hull_nodes.size() < 2) continue;
      p.cliques.push_back({plane.hull_nodes, float(options.plane_truncation * double(plane.hull_nodes.size())), int16_t(kWPlane)});
    }
    // Object segments: 26-connected visible voxels whose appearance says furniture or props, outside planes
    // of walls, floors and ceilings.
    std::vector<uint8_t> in_layout_plane(size_t(n), 0);
    for (const DetectedPlane& plane : planes)
      if (plane.area_m2 >= 1.0)
        for (int node : plane.members) in_layout_plane[size_t(node)] = 1;
    std::vector<uint8_t> object_class(size_t(K), 0);
    for (int k = 0; k < K && k < model.num_classes(); ++k) {
      const int id = model.nyu40_of_class[size_t(k)];
      object_class[size_t(k)] = id > 0 && id < kNumNyu40 && Nyu40Labels()[size_t(id)].nyu4_id >= 3;
    }
    std::vector<uint8_t> cand(size_t(n), 0);
    for (int i = 0; i < n; ++i) {
      if (!visible[size_t(i)] || in_layout_plane[size_t(i)]) continue;
      const float* a = &p.f_appearance[size_t(i) * K];
      const int best = int(std::min_element(a, a + K) - a);
      cand[size_t(i)] = object_class[size_t(best)];
    }
    std::vector<uint8_t> seen(size_t(n), 0);
    std::vector<int> stack, comp;
    const auto& d = grid.dims();
    for (int s = 0; s < n; ++s) {
      if (!cand[size_t(s)] || seen[size_t(s)]) continue;
      comp.clear();
      seen[size_t(s)] = 1;
      stack.push_back(s);
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        comp.push_back(i);
        const auto c = grid.Cell(nodes.voxel[size_t(i)]);
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int x = c[0] + dx, y = c[1] + dy, z = c[2] + dz;
              if (x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] || z >= d[2]) continue;
              const int32_t j = nodes.node_of_voxel[grid.Index(x, y, z)];
              if (j >= 0 && cand[size_t(j)] && !seen[size_t(j)]) seen[size_t(j)] = 1, stack.push_back(j);
            }
      }
      if (int(comp.size()) < options.min_object_voxels) continue;
      std::sort(comp.begin(), comp.end());
      p.cliques.push_back({comp, float(options.object_truncation * double(comp.size())), int16_t(kWObject)});
    }
  }
  return p;
}

CrfEnergy VoxelCrfProblem::Energy(const std::array<double, kNumVoxelCrfWeights>& w, const std::vector<int>* loss_gt) const {
  const int K = num_labels - 1;
  CrfEnergy e(num_nodes, num_labels);
  std::span<float> u = e.mutable_unaries();
  const size_t N = size_t(num_nodes);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, N, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const uint8_t st = state[i];
      u[i] = float(w[kWDepthEmpty] * f_depth_empty[i] + w[kWDensityEmpty] * f_density_empty[i] +
                   w[kWMapOccupiedEmpty] * (st == uint8_t(VoxelState::kOccupied)) +
                   (keep_occupied.empty() || !keep_occupied[i] ? 0.0 : double(kKeepOccupiedCost)));
      const double occ = w[kWDepthOccupied] * f_depth_occ[i] + w[kWDensityOccupied] * f_density_occ[i] +
                         w[kWUnseenOccupied] * (st == uint8_t(VoxelState::kUnknown)) +
                         w[kWMapFreeOccupied] * (st == uint8_t(VoxelState::kFree)) + w[kWOccupiedBias];
      const bool segment = !f_segment.empty();
      for (int k = 0; k < K; ++k)
        u[size_t(k + 1) * N + i] = float(occ + w[kWAppearance] * f_appearance[i * K + k] + w[kWLayout] * f_layout[i * K + k] +
                                         (segment ? w[kWSegment] * f_segment[i * K + k] : 0.0));
      if (loss_gt)
        for (int l = 0; l < num_labels; ++l)
          if (l != (*loss_gt)[i]) u[size_t(l) * N + i] -= 1.0f;
    }
  });
  e.ReserveEdges(edges.size());
  for (const Edge& ed : edges)
    if (w[size_t(ed.type)] > 0) e.AddEdge(ed.i, ed.j, float(w[size_t(ed.type)]));
  for (const Clique& c : cliques) {
    const double wg = w[size_t(c.type)];
    if (!(wg > 0) || c.nodes.size() < 2 || !(c.q > 0) || double(c.q) > 0.5 * double(c.nodes.size())) continue;
    RobustPnParams params;
    params.truncation_q = c.q;
    params.gamma_max = float(wg * c.q);
    params.gamma.assign(size_t(num_labels), 0.f);
    params.gamma[0] = params.gamma_max;  // All empty is never rewarded.
    e.AddRobustPnClique(c.nodes, params);
  }
  return e;
}

std::array<double, kNumVoxelCrfWeights> VoxelCrfProblem::Features(const std::vector<int>& labels) const {
  std::array<double, kNumVoxelCrfWeights> f{};
  const int K = num_labels - 1;
  for (size_t i = 0; i < size_t(num_nodes); ++i) {
    const int l = labels[i];
    const uint8_t st = state[i];
    if (l == 0) {
      f[kWDepthEmpty] += f_depth_empty[i];
      f[kWDensityEmpty] += f_density_empty[i];
      f[kWMapOccupiedEmpty] += st == uint8_t(VoxelState::kOccupied);
    } else {
      f[kWMapFreeOccupied] += st == uint8_t(VoxelState::kFree);
      f[kWAppearance] += f_appearance[i * K + size_t(l - 1)];
      f[kWDepthOccupied] += f_depth_occ[i];
      f[kWDensityOccupied] += f_density_occ[i];
      f[kWUnseenOccupied] += st == uint8_t(VoxelState::kUnknown);
      f[kWOccupiedBias] += 1.0;
      f[kWLayout] += f_layout[i * K + size_t(l - 1)];
      if (!f_segment.empty()) f[kWSegment] += f_segment[i * K + size_t(l - 1)];
    }
  }
  for (const Edge& e : edges) f[size_t(e.type)] += labels[size_t(e.i)] != labels[size_t(e.j)];
  std::vector<int> count(static_cast<size_t>(num_labels));
  for (const Clique& c : cliques) {
    std::fill(count.begin(), count.end(), 0);
    for (int node : c.nodes) ++count[size_t(labels[size_t(node)])];
    int best = 0;
    for (int l = 1; l < num_labels; ++l) best = std::max(best, count[size_t(l)]);
    f[size_t(c.type)] += std::min(double(c.q), double(c.nodes.size()) - best);
  }
  return f;
}

// ---------------------------------------------------------------------------------------------------------
// Local re-solves.

namespace {
inline uint64_t FloatBits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}
}  // namespace

std::vector<uint64_t> NodeFingerprints(const VoxelCrfProblem& p) {
  const size_t N = size_t(p.num_nodes), K = size_t(std::max(0, p.num_labels - 1));
  std::vector<uint64_t> fp(N, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, N, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      uint64_t h = HashCombine(0, p.state[i]);
      h = HashCombine(h, p.keep_occupied.empty() ? 2u : p.keep_occupied[i]);
      h = HashCombine(h, FloatBits(p.f_depth_empty[i]) | FloatBits(p.f_density_empty[i]) << 32);
      h = HashCombine(h, FloatBits(p.f_depth_occ[i]) | FloatBits(p.f_density_occ[i]) << 32);
      for (size_t k = 0; k < K; ++k) {
        h = HashCombine(h, FloatBits(p.f_appearance[i * K + k]) | FloatBits(p.f_layout[i * K + k]) << 32);
        if (!p.f_segment.empty()) h = HashCombine(h, FloatBits(p.f_segment[i * K + k]));
      }
      fp[i] = h;
    }
  });
  // Edges and cliques: a sum over them (their order in the lists does not matter).
  std::vector<uint64_t> sum(N, 0);
  for (const VoxelCrfProblem::Edge& e : p.edges) {
    sum[size_t(e.i)] += HashCombine(HashCombine(1, uint64_t(e.j)), uint64_t(e.type));
    sum[size_t(e.j)] += HashCombine(HashCombine(1, uint64_t(e.i)), uint64_t(e.type));
  }
  for (const VoxelCrfProblem::Clique& c : p.cliques) {
    uint64_t h = HashCombine(HashCombine(2, uint64_t(c.type)), FloatBits(c.q));
    for (int v : c.nodes) h = HashCombine(h, uint64_t(v));
    for (int v : c.nodes) sum[size_t(v)] += h;
  }
  for (size_t i = 0; i < N; ++i) fp[i] = HashCombine(fp[i], sum[i]);
  return fp;
}

std::vector<uint8_t> ChangedNodes(const VoxelCrfProblem& problem, const std::vector<uint64_t>& before,
                                  const std::vector<uint64_t>& after, int rings) {
  const size_t N = after.size();
  std::vector<uint8_t> changed(N, 1);
  if (before.size() != N) return changed;
  for (size_t i = 0; i < N; ++i) changed[i] = before[i] != after[i];
  std::vector<uint8_t> next;
  for (int ring = 0; ring < rings; ++ring) {
    next = changed;
    for (const VoxelCrfProblem::Edge& e : problem.edges)
      if (changed[size_t(e.i)] || changed[size_t(e.j)]) next[size_t(e.i)] = next[size_t(e.j)] = 1;
    changed.swap(next);
  }
  return changed;
}

// ---------------------------------------------------------------------------------------------------------
// Alg. 1.

Status SolveVoxelCrf(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev, double floor_z,
                     double ceiling_z, const VoxelCrfModel& model, const VoxelCrfOptions& options, VoxelCrfResult* result) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("voxel CRF options: " + error);
  if (model.num_classes() != ev.num_classes)
    return Status::InvalidInput("voxel CRF model has " + std::to_string(model.num_classes()) + " classes, the evidence " +
                                std::to_string(ev.num_classes) + " (hint: train both with `semvox train`)");
  const auto t_all = Clock::now();
  *result = VoxelCrfResult{};
  const int n = int(nodes.size());
  auto t_phase = Clock::now();
  const std::vector<DetectedPlane> planes = DetectPlanes(grid, nodes, ev, options.planes);
  result->num_planes = int(planes.size());
  result->seconds_planes = Seconds(t_phase);
  // V_0: the first voxel the map holds occupied along each ray.
  std::vector<int> labels(size_t(n), 0);
  for (int i = 0; i < n; ++i) labels[size_t(i)] = nodes.initial_state[size_t(i)] == uint8_t(VoxelState::kOccupied) ? 1 : 0;
  t_phase = Clock::now();
  const std::vector<float> starts = ComputeRayStarts(grid, nodes, ev);
  std::vector<int32_t> vis = ComputeVisibility(grid, nodes, ev, labels, &starts);
  result->seconds_ray_starts = Seconds(t_phase);
  std::vector<int> previous;
  VoxelCrfProblem problem;
  std::vector<uint64_t> fingerprints;  // Of the previous iteration's problem (local re-solves).
  for (int it = 0; it < options.max_iterations; ++it) {
    const auto t0 = Clock::now();
    VoxelCrfIteration rec;
    problem = BuildVoxelCrfProblem(grid, nodes, ev, floor_z, ceiling_z, model, planes, options, vis);
    rec.seconds_build = Seconds(t0);
    t_phase = Clock::now();
    const CrfEnergy energy = problem.Energy(model.w);
    rec.seconds_energy = Seconds(t_phase);
    // After the first iteration: re-solve where the new visibility changed the problem (reiterate_rings).
    std::vector<uint8_t> movable;
    if (options.reiterate_rings >= 0 && options.max_iterations > 1) {
      std::vector<uint64_t> now = NodeFingerprints(problem);
      if (it > 0) movable = ChangedNodes(problem, fingerprints, now, options.reiterate_rings);
      fingerprints = std::move(now);
    }
    rec.movable_nodes = movable.empty() ? n : int64_t(std::count(movable.begin(), movable.end(), uint8_t(1)));
    AlphaExpansionOptions solver = options.solver;
    solver.max_sweeps = std::min(solver.max_sweeps, options.max_sweeps);
    std::vector<CrfLabel> crf_labels;
    if (it > 0) {
      solver.initial_labelling = InitialLabelling::kGiven;
      crf_labels.assign(labels.begin(), labels.end());
    }
    CrfSolverSummary summary;
    t_phase = Clock::now();
    SEMVOX_RETURN_IF_ERROR(MinimizeWithAlphaExpansion(energy, solver, &crf_labels, &summary, movable.empty() ? nullptr : &movable));
    rec.seconds_expansion = Seconds(t_phase);
    rec.seconds_max_flow = summary.max_flow_seconds;
    labels.assign(crf_labels.begin(), crf_labels.end());
    rec.energy_initial = summary.initial_energy;
    rec.energy_final = summary.final_energy;
    rec.energy_per_sweep = summary.energy_per_sweep;
    rec.sweeps = summary.num_sweeps;
    rec.edges = problem.edges.size();
    rec.cliques = problem.cliques.size();
    if (!previous.empty())
      for (int i = 0; i < n; ++i) rec.changed_labels += labels[size_t(i)] != previous[size_t(i)];
    else
      rec.changed_labels = n;
    previous = labels;
    // Step 4: visibility from the new labels.
    t_phase = Clock::now();
    std::vector<int32_t> next = ComputeVisibility(grid, nodes, ev, labels, &starts);
    rec.seconds_visibility = Seconds(t_phase);
    for (size_t r = 0; r < next.size(); ++r) rec.changed_visibility += next[r] != vis[r];
    vis = std::move(next);
    for (int32_t v : vis) rec.visible_nodes += v >= 0;
    rec.seconds = Seconds(t0);
    SEMVOX_INFO("voxel CRF iteration " << it + 1 << ": energy " << rec.energy_initial << " -> " << rec.energy_final << " in "
                                       << rec.sweeps << " sweeps, " << rec.edges << " edges, " << rec.cliques << " cliques, "
                                       << rec.changed_visibility << " rays changed their visible voxel (" << rec.seconds << " s)");
    result->iterations.push_back(std::move(rec));
    const double moved = double(result->iterations.back().changed_visibility);
    if (moved <= options.visibility_tolerance * double(std::max<size_t>(1, vis.size()))) break;
    if (it > 0 && moved > (1.0 - options.visibility_min_progress) * double(result->iterations[size_t(it) - 1].changed_visibility)) {
      SEMVOX_INFO("voxel CRF: visibility no longer settling (" << moved << " rays moved after "
                  << result->iterations[size_t(it) - 1].changed_visibility << "), stopping after iteration " << it + 1);
      break;
    }
  }
  for (const auto& c : problem.cliques) result->num_object_cliques += c.type == kWObject;
  // Confidence: p(l_i | neighbours) from the unary and pairwise terms of the final energy.
  t_phase = Clock::now();
  const CrfEnergy energy = problem.Energy(model.w);
  const NodeIncidence inc = energy.EdgeIncidence();
  const int L = energy.num_labels();
  result->confidence.assign(size_t(n), 0.f);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& r) {
    std::vector<double> e(static_cast<size_t>(L));
    for (int i = r.begin(); i != r.end(); ++i) {
      for (int l = 0; l < L; ++l) e[size_t(l)] = energy.unary(i, l);
      for (int ei : inc.Of(i)) {
        const CrfEnergy::Edge& ed = energy.edges()[size_t(ei)];
        const int other = labels[size_t(ed.i == i ? ed.j : ed.i)];
        for (int l = 0; l < L; ++l) e[size_t(l)] += l != other ? ed.weight : 0.0;
      }
      const double m = *std::min_element(e.begin(), e.end());
      double z = 0;
      for (double v : e) z += std::exp(-(v - m));
      result->confidence[size_t(i)] = float(std::exp(-(e[size_t(labels[size_t(i)])] - m)) / z);
    }
  });
  result->seconds_confidence = Seconds(t_phase);
  result->visible.assign(size_t(n), 0);
  for (int32_t v : vis)
    if (v >= 0) result->visible[size_t(v)] = 1;
  result->visibility = std::move(vis);
  result->labels = std::move(labels);
  result->seconds = Seconds(t_all);
  return Status::Ok();
}

}  // namespace semvox
