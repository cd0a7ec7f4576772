// Voxel-CRF: energy/feature consistency, visibility (Eq. 9) on an analytic scene, plane
// completion behind a cabinet, learning, and the map.ot / voxels.ply round trips.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "core/labels.h"
#include "core/ply.h"
#include "mapping/octomap_io.h"
#include "mapping/voxelizer.h"
#include "perception/training_data.h"
#include "render/view_renderer.h"
#include "render/views.h"
#include "scenegen/mesh_builder.h"
#include "tests/test_util.h"
#include "voxelcrf/planes.h"
#include "voxelcrf/semantic_map.h"
#include "voxelcrf/voxel_crf.h"
#include "voxelcrf/voxel_crf_learning.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {
namespace {

using V = Eigen::Vector3d;

// A random problem in feature form over a small 3D chain of nodes, with edges and cliques of both kinds.
VoxelCrfProblem RandomProblem(int n, int K, std::mt19937_64* rng) {
  std::uniform_real_distribution<float> u(0.f, 3.f);
  VoxelCrfProblem p;
  p.num_nodes = n;
  p.num_labels = K + 1;
  for (int i = 0; i < n; ++i) {
    p.f_depth_empty.push_back(u(*rng));
    p.f_density_empty.push_back(u(*rng));
    p.f_depth_occ.push_back(u(*rng));
    p.f_density_occ.push_back(u(*rng));
    p.state.push_back(uint8_t((*rng)() % 3));
    for (int k = 0; k < K; ++k) p.f_appearance.push_back(u(*rng)), p.f_layout.push_back(u(*rng)), p.f_segment.push_back(i % 3 ? u(*rng) : 0.f);
  }
  for (int i = 0; i + 1 < n; ++i) p.edges.push_back({i, i + 1, int16_t(kWPairwise3d + int((*rng)() % 10))});
  for (int i = 0; i + 3 < n; i += 2) p.edges.push_back({i, i + 3, int16_t(kWPairwise2d)});
  p.cliques.push_back({{0, 1, 2, 3, 4, 5}, 1.5f, int16_t(kWPlane)});
  p.cliques.push_back({{3, 4, 5, 6}, 2.0f, int16_t(kWObject)});
  return p;
}

TEST(VoxelCrfProblem, EnergyIsTheDotProductOfWeightsAndFeatures) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const int K = 1 + int(rng() % 4), n = 8 + int(rng() % 6);
    const VoxelCrfProblem p = RandomProblem(n, K, &rng);
    std::array<double, kNumVoxelCrfWeights> w{};
    std::uniform_real_distribution<double> uw(0.0, 2.0);
    for (double& x : w) x = uw(rng);
    w[kWOccupiedBias] = uw(rng) - 1.0;
    std::vector<int> gt(static_cast<size_t>(n));
    for (int& g : gt) g = int(rng() % uint64_t(K + 1));
    const CrfEnergy e = p.Energy(w);
    const CrfEnergy aug = p.Energy(w, &gt);
    std::string error;
    ASSERT_TRUE(e.Check(&error)) << error;
    for (int s = 0; s < 20; ++s) {
      std::vector<int> l(static_cast<size_t>(n));
      for (int& x : l) x = int(rng() % uint64_t(K + 1));
      const auto f = p.Features(l);
      double dot = 0;
      for (int i = 0; i < kNumVoxelCrfWeights; ++i) dot += w[size_t(i)] * f[size_t(i)];
      const std::vector<CrfLabel> cl(l.begin(), l.end());
      EXPECT_NEAR(e.Evaluate(cl), dot, 1e-3 * (1 + std::abs(dot)));
      // Loss-augmented: E - Delta (Delta = number of nodes off the ground truth).
      EXPECT_NEAR(aug.Evaluate(cl), dot - HammingLoss(l, gt) * n, 1e-3 * (1 + std::abs(dot)));
    }
  }
}

// The local re-solve's change detection: a node whose unary features, edges or cliques change is flagged,
// with its neighbours out to `rings` edges; nothing else is.
TEST(VoxelCrfProblem, ChangedNodesFollowEveryKindOfTermAndTheRings) {
  std::mt19937_64 rng(5);
  const int n = 12, K = 3;
  const VoxelCrfProblem p = RandomProblem(n, K, &rng);
  const std::vector<uint64_t> before = NodeFingerprints(p);
  auto flagged = [&](const VoxelCrfProblem& q, int rings) {
    const std::vector<uint8_t> c = ChangedNodes(q, before, NodeFingerprints(q), rings);
    std::vector<int> out;
    for (int i = 0; i < n; ++i)
      if (c[size_t(i)]) out.push_back(i);
    return out;
  };
  EXPECT_EQ(flagged(p, 0), std::vector<int>{});
  EXPECT_EQ(flagged(p, 3), std::vector<int>{});
  VoxelCrfProblem q = p;
  q.f_appearance[size_t(9 * K + 1)] += 0.5f;  // Node 9; its edges: 8-9, 9-10 (chain) and 6-9 (i, i + 3).
  EXPECT_EQ(flagged(q, 0), (std::vector<int>{9}));
  EXPECT_EQ(flagged(q, 1), (std::vector<int>{6, 8, 9, 10}));
  EXPECT_EQ(flagged(q, 2), (std::vector<int>{5, 6, 7, 8, 9, 10, 11}));
  q = p;
  q.f_depth_empty[2] = 0;
  q.state[11] = uint8_t((q.state[11] + 1) % 3);
  EXPECT_EQ(flagged(q, 0), (std::vector<int>{2, 11}));
  q = p;
  q.edges[3].type = int16_t(q.edges[3].type == kWPairwise2d ? kWPairwise3d : kWPairwise2d);  // Edge 3-4.
  EXPECT_EQ(flagged(q, 0), (std::vector<int>{3, 4}));
  q = p;
  q.edges.push_back({1, 11, int16_t(kWPairwise2d)});
  EXPECT_EQ(flagged(q, 0), (std::vector<int>{1, 11}));
  q = p;
  q.cliques[1].q = 2.5f;  // Members 3, 4, 5, 6.
  EXPECT_EQ(flagged(q, 0), (std::vector<int>{3, 4, 5, 6}));
  q = p;
  std::reverse(q.edges.begin(), q.edges.end());  // The same terms in another order.
  EXPECT_EQ(flagged(q, 0), std::vector<int>{});
  // Another node count: every node.
  EXPECT_EQ(ChangedNodes(p, std::vector<uint64_t>(size_t(n - 1)), before, 0), std::vector<uint8_t>(size_t(n), 1));
}

TEST(VoxelCrfLearning, StructuredSvmLowersTheTrainingError) {
  // Examples whose appearance feature is informative while the initial weights ignore it and favour empty.
  std::mt19937_64 rng(3);
  std::vector<VoxelCrfTrainingExample> examples;
  const int K = 3, n = 300;
  for (int e = 0; e < 3; ++e) {
    VoxelCrfTrainingExample ex;
    VoxelCrfProblem& p = ex.problem;
    p.num_nodes = n;
    p.num_labels = K + 1;
    std::uniform_real_distribution<float> noise(0.f, 0.5f);
    for (int i = 0; i < n; ++i) {
      const int g = (i / 10) % (K + 1);  // Runs of ten.
      ex.gt.push_back(g);
      p.f_depth_empty.push_back(g == 0 ? noise(rng) : 2.f + noise(rng));
      p.f_density_empty.push_back(0.f);
      p.f_depth_occ.push_back(g == 0 ? 2.f + noise(rng) : noise(rng));
      p.f_density_occ.push_back(0.f);
      p.state.push_back(uint8_t(VoxelState::kOccupied));
      for (int k = 0; k < K; ++k) p.f_appearance.push_back(k + 1 == g ? noise(rng) : 1.5f + noise(rng)), p.f_layout.push_back(0.f);
    }
    for (int i = 0; i + 1 < n; ++i) p.edges.push_back({i, i + 1, int16_t(kWPairwise3d)});
    examples.push_back(std::move(ex));
  }
  std::array<double, kNumVoxelCrfWeights> w0{};
  w0[kWDepthOccupied] = 0.1;
  w0[kWDepthEmpty] = 0.1;
  w0[kWOccupiedBias] = 1.0;  // Everything empty at first.
  auto error_of = [&](const std::array<double, kNumVoxelCrfWeights>& w) {
    double sum = 0;
    for (const auto& ex : examples) {
      std::vector<CrfLabel> labels;
      CrfSolverSummary s;
      EXPECT_TRUE(MinimizeWithAlphaExpansion(ex.problem.Energy(w), AlphaExpansionOptions{}, &labels, &s).ok());
      sum += HammingLoss(std::vector<int>(labels.begin(), labels.end()), ex.gt);
    }
    return sum / double(examples.size());
  };
  const double before = error_of(w0);
  VoxelCrfLearningOptions options;
  options.epochs = 15;
  VoxelCrfLearningSummary summary;
  Result<std::array<double, kNumVoxelCrfWeights>> w = LearnVoxelCrfWeights(examples, w0, options, &summary);
  ASSERT_TRUE(w.ok()) << w.status().message();
  const double after = error_of(*w);
  EXPECT_GT(before, 0.7);
  EXPECT_LT(after, 0.05);
  EXPECT_GT((*w)[kWAppearance], 0.0);
  for (int i = 0; i < kNumVoxelCrfWeights; ++i) {
    if (i != kWOccupiedBias) {
      EXPECT_GE((*w)[size_t(i)], 0.0) << "weight " << i;
    }
  }
  // A frozen weight keeps its initial value while the others still learn (`semvox train
  // --voxel-crf-appearance-weight`): here the appearance weight held at 0 leaves the labels to depth alone.
  options.frozen[kWAppearance] = true;
  Result<std::array<double, kNumVoxelCrfWeights>> held = LearnVoxelCrfWeights(examples, w0, options, &summary);
  ASSERT_TRUE(held.ok()) << held.status().message();
  EXPECT_EQ((*held)[kWAppearance], 0.0);
  EXPECT_NE((*held)[kWDepthOccupied], w0[kWDepthOccupied]);
  EXPECT_GT(error_of(*held), after + 0.2);  // Without appearance the classes cannot be told apart.
}

// ---- Analytic scenes ----

Scene MeshScene(Mesh mesh) {
  Scene s;
  s.format = "test";
  s.mesh = std::move(mesh);
  return s;
}

VoxelMap MapOf(const Scene& scene) {
  VoxelizeOptions vo;
  Result<VoxelMap> m = Voxelize(scene, vo);
  EXPECT_TRUE(m.ok()) << m.status().message();
  return std::move(m).value();
}

// A 4 x 3 x 2.5 m room of 0.1 m thick boxes: floor, ceiling, the west, east and south walls, and the north
// wall from x = -0.1 to north_wall_end_x (4.1: closed).
void AddBoxRoom(MeshBuilder* b, double north_wall_end_x) {
  b->AddBox({-0.1, -0.1, -0.1}, {4.1, 3.1, 0.0}, Rgb8{150, 150, 150}, FaceTags{nyu40::kFloor});
  b->AddBox({-0.1, -0.1, 2.5}, {4.1, 3.1, 2.6}, Rgb8{200, 200, 200}, FaceTags{nyu40::kCeiling});
  b->AddBox({-0.1, -0.1, 0.0}, {0.0, 3.1, 2.5}, Rgb8{180, 90, 90}, FaceTags{nyu40::kWall});
  b->AddBox({4.0, -0.1, 0.0}, {4.1, 3.1, 2.5}, Rgb8{180, 90, 90}, FaceTags{nyu40::kWall});
  b->AddBox({-0.1, -0.1, 0.0}, {4.1, 0.0, 2.5}, Rgb8{180, 90, 90}, FaceTags{nyu40::kWall});
  b->AddBox({-0.1, 3.0, 0.0}, {north_wall_end_x, 3.1, 2.5}, Rgb8{180, 90, 90}, FaceTags{nyu40::kWall});
}

TEST(VoxelCrfVisibility, FirstOccupiedVoxelAlongEachRayIsExact) {
  // A room with a free-standing panel at x = 2.0 in front of the east wall at x = 4.0.
  MeshBuilder b;
  AddBoxRoom(&b, 4.1);
  b.AddQuad({2.0, 1.0, 0.5}, {2.0, 2.0, 0.5}, {2.0, 2.0, 2.0}, {2.0, 1.0, 2.0}, Rgb8{20, 200, 20}, FaceTags{nyu40::kPicture});
  const Scene scene = MeshScene(b.Take());
  const VoxelMap map = MapOf(scene);
  const VoxelGrid& g = map.grid;
  const VoxelCrfNodes nodes = SelectVoxelCrfNodes(g, map.floor_z, map.ceiling_z, VoxelEvidenceOptions{});
  VoxelEvidence ev;
  ev.num_classes = 1;
  ev.origins.push_back(Eigen::Vector3f(0.5f, 1.3f, 1.1f));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> uy(1.15f, 1.85f), uz(0.9f, 1.35f);
  std::vector<Eigen::Vector3f> targets;
  for (int k = 0; k < 40; ++k) {
    const Eigen::Vector3f target(2.0f, uy(rng), uz(rng));
    EvidenceRay r;
    r.direction = (target - ev.origins[0]).normalized();
    r.max_t = 6.0f;
    ev.rays.push_back(r);
    targets.push_back(target);
  }
  auto expect_node_at = [&](int32_t node, const Eigen::Vector3f& p) {
    ASSERT_GE(node, 0);
    const auto c = g.CellOf(p.cast<double>());
    EXPECT_EQ(nodes.voxel[size_t(node)], g.Index(c[0], c[1], c[2])) << "point " << p.transpose();
  };
  std::vector<int> labels(nodes.size(), 0);
  for (size_t i = 0; i < nodes.size(); ++i) labels[i] = nodes.initial_state[i] == uint8_t(VoxelState::kOccupied);
  // Every walk twice: from the ray's origin and from its start (ComputeRayStarts), the same nodes.
  const std::vector<float> starts = ComputeRayStarts(g, nodes, ev);
  for (float t : starts) EXPECT_GT(t, 0.f);  // The origin is in free space outside the CRF.
  auto visibility = [&]() {
    std::vector<int32_t> v = ComputeVisibility(g, nodes, ev, labels);
    EXPECT_EQ(ComputeVisibility(g, nodes, ev, labels, &starts), v);
    return v;
  };
  std::vector<int32_t> vis = visibility();
  for (size_t k = 0; k < targets.size(); ++k) expect_node_at(vis[k], targets[k]);  // The panel.
  // Label the panel empty: each ray now sees the east wall where the ray meets x = 4.0 ...
  for (size_t i = 0; i < nodes.size(); ++i) {
    const auto c = g.Cell(nodes.voxel[i]);
    if (std::abs(g.CellCenter(c[0], c[1], c[2]).x() - 2.025) < 1e-6) labels[i] = 0;
  }
  vis = visibility();
  for (size_t k = 0; k < targets.size(); ++k) {
    const Eigen::Vector3f d = ev.rays[k].direction;
    const float t = (4.0f - ev.origins[0].x()) / d.x();
    expect_node_at(vis[k], ev.origins[0] + t * d);
  }
  // ... and with everything empty no ray sees anything.
  std::fill(labels.begin(), labels.end(), 0);
  vis = visibility();
  for (int32_t v : vis) EXPECT_EQ(v, -1);
}

TEST(VoxelCrfVisibility, RayStartsSkippingEmptyBlocksKeepEveryWalk) {
  // ComputeRayStarts crosses blocks without nodes in one step: for rays from several cameras in all directions
  // (grazing the walls, ending in free space, leaving the grid, from a camera outside the grid) and random
  // labellings, the walk from each start sees exactly the node the walk from the ray's origin sees.
  MeshBuilder b;
  AddBoxRoom(&b, 2.0);  // A gap in the north wall from x = 2 to 4.
  b.AddBox({1.2, 1.0, 0.0}, {2.1, 1.6, 0.7}, Rgb8{20, 200, 20}, FaceTags{nyu40::kTable});
  const Scene scene = MeshScene(b.Take());
  const VoxelMap map = MapOf(scene);
  const VoxelGrid& g = map.grid;
  const VoxelCrfNodes nodes = SelectVoxelCrfNodes(g, map.floor_z, map.ceiling_z, VoxelEvidenceOptions{});
  VoxelEvidence ev;
  ev.num_classes = 1;
  ev.origins = {Eigen::Vector3f(0.7f, 0.6f, 1.2f), Eigen::Vector3f(3.1f, 2.2f, 1.7f), Eigen::Vector3f(2.0f, 1.3f, 2.2f),
                Eigen::Vector3f(9.0f, 1.0f, 1.0f)};  // The last outside the grid.
  std::mt19937_64 rng(7);
  std::normal_distribution<float> n01;
  std::uniform_real_distribution<float> length(0.2f, 7.0f);
  for (int k = 0; k < 6000; ++k) {
    EvidenceRay r;
    r.origin = k % int(ev.origins.size());
    Eigen::Vector3f d(n01(rng), n01(rng), n01(rng));
    if (k % 7 == 0) d.z() = 0;                     // Level rays along the grid's planes.
    if (k % 11 == 0) d = Eigen::Vector3f(1, 0, 0);  // Along an axis.
    r.direction = d.normalized();
    r.max_t = length(rng);
    ev.rays.push_back(r);
  }
  const std::vector<float> starts = ComputeRayStarts(g, nodes, ev);
  size_t started = 0;
  for (float t : starts) started += t >= 0;
  EXPECT_GT(started, ev.rays.size() / 2);
  std::uniform_real_distribution<double> u(0, 1);
  for (double keep : {1.0, 0.5, 0.05}) {
    std::vector<int> labels(nodes.size(), 0);
    for (size_t i = 0; i < nodes.size(); ++i)
      labels[i] = (nodes.initial_state[i] == uint8_t(VoxelState::kOccupied) || u(rng) < 0.02) && u(rng) < keep;
    const std::vector<int32_t> plain = ComputeVisibility(g, nodes, ev, labels);
    const std::vector<int32_t> from_starts = ComputeVisibility(g, nodes, ev, labels, &starts);
    size_t seen = 0, differ = 0;
    for (size_t k = 0; k < plain.size(); ++k) seen += plain[k] >= 0, differ += plain[k] != from_starts[k];
    EXPECT_EQ(differ, 0u) << "labels kept with probability " << keep;
    EXPECT_GT(seen, 0u);
  }
}

// A room whose south wall is hidden behind a cabinet standing against it: the scan has no wall there.
struct CabinetRoom {
  Mesh mesh;
  // The wall voxels behind the cabinet (ground truth: wall) and the cabinet's inside (ground truth: empty).
  static bool BehindCabinet(const V& c) { return c.y() > 0 && c.y() < 0.05 && c.x() > 1.6 && c.x() < 2.4 && c.z() > 0.1 && c.z() < 1.35; }
  static bool InsideCabinet(const V& c) { return c.y() > 0.12 && c.y() < 0.43 && c.x() > 1.62 && c.x() < 2.38 && c.z() > 0.12 && c.z() < 1.38; }
};

CabinetRoom MakeCabinetRoom() {
  MeshBuilder b;
  const FaceTags wall{nyu40::kWall}, cab{nyu40::kCabinet};
  const Rgb8 wc{200, 190, 170}, cc{120, 70, 30};
  b.AddQuad({0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}, Rgb8{140, 120, 100}, FaceTags{nyu40::kFloor});
  b.AddQuad({0, 0, 2.5}, {0, 3, 2.5}, {4, 3, 2.5}, {4, 0, 2.5}, Rgb8{240, 240, 240}, FaceTags{nyu40::kCeiling});
  // South wall (y = 0, facing +y) without the part the cabinet covers.
  b.AddQuad({0, 0, 0}, {0, 0, 2.5}, {1.5, 0, 2.5}, {1.5, 0, 0}, wc, wall);
  b.AddQuad({2.5, 0, 0}, {2.5, 0, 2.5}, {4, 0, 2.5}, {4, 0, 0}, wc, wall);
  b.AddQuad({1.5, 0, 1.5}, {1.5, 0, 2.5}, {2.5, 0, 2.5}, {2.5, 0, 1.5}, wc, wall);
  b.AddQuad({0, 3, 0}, {4, 3, 0}, {4, 3, 2.5}, {0, 3, 2.5}, wc, wall);
  b.AddQuad({0, 0, 0}, {0, 3, 0}, {0, 3, 2.5}, {0, 0, 2.5}, wc, wall);
  b.AddQuad({4, 0, 0}, {4, 0, 2.5}, {4, 3, 2.5}, {4, 3, 0}, wc, wall);
  // Cabinet x [1.5, 2.5], y [0, 0.5], z [0, 1.5]: front, top and sides (no back, no bottom).
  b.AddQuad({1.5, 0.5, 0}, {2.5, 0.5, 0}, {2.5, 0.5, 1.5}, {1.5, 0.5, 1.5}, cc, cab);
  b.AddQuad({1.5, 0, 1.5}, {1.5, 0.5, 1.5}, {2.5, 0.5, 1.5}, {2.5, 0, 1.5}, cc, cab);
  b.AddQuad({1.5, 0, 0}, {1.5, 0.5, 0}, {1.5, 0.5, 1.5}, {1.5, 0, 1.5}, cc, cab);
  b.AddQuad({2.5, 0, 0}, {2.5, 0, 1.5}, {2.5, 0.5, 1.5}, {2.5, 0.5, 0}, cc, cab);
  return CabinetRoom{b.Take()};
}

// The depth evidence skips whole blocks of nodes that lie behind every surface a view sees (occlusion
// culling); the counts and sums must be those of projecting every node into every view.
TEST(VoxelEvidence, OcclusionCullingKeepsTheDepthEvidenceOfEveryNode) {
  CabinetRoom room = MakeCabinetRoom();
  const Scene scene = MeshScene(room.mesh);
  const VoxelMap map = MapOf(scene);
  const VoxelGrid& g = map.grid;
  const VoxelEvidenceOptions eo;
  const VoxelCrfNodes nodes = SelectVoxelCrfNodes(g, map.floor_z, map.ceiling_z, eo);
  EvidenceAccumulator acc(g, nodes, 3, eo);
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok());
  ViewsOptions vo;
  vo.width = 160;
  vo.height = 120;
  vo.tilted_ring_deg = 40;
  std::vector<uint16_t> observing(nodes.size(), 0);
  std::vector<double> sum_f(nodes.size(), 0.0);
  size_t occluded = 0;
  Result<ViewSet> views = RenderViews(*renderer, map, vo, [&](const ViewRecord& r, const RenderedView& view) {
    if (!r.kept()) return Status::Ok();
    acc.AddDepthView(view);
    // Reference: every node projected into the view, no culling.
    const Eigen::Isometry3d cfw = view.world_from_camera.inverse();
    const double sigma = eo.depth_sigma_voxels * g.resolution();
    for (size_t i = 0; i < nodes.size(); ++i) {
      const auto c = g.Cell(nodes.voxel[i]);
      const Eigen::Vector3f p = (cfw.linear().cast<float>() * g.CellCenter(c[0], c[1], c[2]).cast<float>() + cfw.translation().cast<float>());
      if (p.z() <= 1e-3f) continue;
      const float u = float(view.camera.fx) * p.x() / p.z() + float(view.camera.cx), v = float(view.camera.fy) * p.y() / p.z() + float(view.camera.cy);
      if (!(u >= 0 && u < float(view.camera.width) && v >= 0 && v < float(view.camera.height))) continue;
      const float dm = view.depth.at(int(u), int(v));
      if (dm <= 0) continue;
      const double delta = double(p.z()) - double(dm);
      if (delta > 1.5 * sigma) {
        ++occluded;
        continue;
      }
      ++observing[i];
      sum_f[i] += std::exp(-delta * delta / (2 * sigma * sigma));
    }
    return Status::Ok();
  });
  ASSERT_TRUE(views.ok()) << views.status().message();
  EXPECT_GT(occluded, nodes.size());  // The cabinet and the walls hide many nodes from many views.
  const VoxelEvidence ev = std::move(acc).Finish();
  size_t observed = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    ASSERT_EQ(ev.observing_views[i], observing[i]) << "node " << i;
    if (observing[i] == 0) continue;
    ++observed;
    EXPECT_NEAR(ev.depth_agreement[i], sum_f[i] / observing[i], 1e-4) << "node " << i;
  }
  EXPECT_GT(observed, nodes.size() / 4);
}

// BuildVoxelCrfProblem's passes over rays, nodes and views run in parallel (fixed node ranges, views one by
// one): the appearance sums, the 3D edges and the 2D edges of a cabinet room with classified views equal
// those of plain serial passes written out here.
TEST(VoxelCrfProblem, ParallelBuildEqualsPlainSerialPasses) {
  CabinetRoom room = MakeCabinetRoom();
  const Scene scene = MeshScene(room.mesh);
  const VoxelMap map = MapOf(scene);
  const VoxelGrid& g = map.grid;
  const int K = 3;
  const VoxelCrfNodes nodes = SelectVoxelCrfNodes(g, map.floor_z, map.ceiling_z, VoxelEvidenceOptions{});
  EvidenceAccumulator acc(g, nodes, K, VoxelEvidenceOptions{});
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  ASSERT_TRUE(renderer.ok());
  ViewsOptions vo;
  vo.width = 160;
  vo.height = 120;
  vo.tilted_ring_deg = 40;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> unit(0.05f, 1.0f);
  Result<ViewSet> views = RenderViews(*renderer, map, vo, [&](const ViewRecord& r, const RenderedView& view) {
    if (!r.kept()) return Status::Ok();
    acc.AddDepthView(view);
    std::vector<float> probs(size_t(view.camera.width) * view.camera.height * K);
    for (size_t i = 0; i < probs.size(); i += K) {  // Random distributions: sums that round differently by order.
      float sum = 0;
      for (int k = 0; k < K; ++k) sum += probs[i + size_t(k)] = unit(rng);
      for (int k = 0; k < K; ++k) probs[i + size_t(k)] /= sum;
    }
    acc.AddClassifiedView(view, nullptr, probs);
    return Status::Ok();
  });
  ASSERT_TRUE(views.ok()) << views.status().message();
  const VoxelEvidence ev = std::move(acc).Finish();
  std::vector<int> labels(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) labels[i] = nodes.initial_state[i] == uint8_t(VoxelState::kOccupied);
  const std::vector<int32_t> vis = ComputeVisibility(g, nodes, ev, labels);
  const VoxelCrfModel model = VoxelCrfModel::Default({nyu40::kWall, nyu40::kFloor, nyu40::kCabinet}, {"wall", "floor", "cabinet"});
  const VoxelCrfProblem p = BuildVoxelCrfProblem(g, nodes, ev, map.floor_z, map.ceiling_z, model, {}, VoxelCrfOptions{}, vis);
  const size_t n = nodes.size();

  // Appearance: one pass over the rays, -log(max(mean, 1e-3)).
  std::vector<float> app(n * K, 0.f);
  std::vector<int> count(n, 0);
  for (size_t r = 0; r < ev.rays.size(); ++r) {
    if (vis[r] < 0) continue;
    for (int k = 0; k < K; ++k) app[size_t(vis[r]) * K + size_t(k)] += ev.observations[size_t(ev.rays[r].observation) * K + size_t(k)];
    ++count[size_t(vis[r])];
  }
  size_t visible = 0;
  for (size_t i = 0; i < n; ++i) {
    if (count[i] == 0) continue;
    ++visible;
    for (int k = 0; k < K; ++k)
      ASSERT_EQ(p.f_appearance[i * K + size_t(k)], -std::log(std::max(app[i * K + size_t(k)] / float(count[i]), 1e-3f))) << "node " << i;
  }
  EXPECT_GT(visible, n / 10);

  // 3D edges: node by node, +x, +y, +z neighbours that are nodes (their types are per-edge values).
  const auto& d = g.dims();
  const int64_t stride[3] = {1, d[0], int64_t(d[0]) * d[1]};
  std::vector<std::pair<int, int>> edges;
  for (size_t i = 0; i < n; ++i) {
    const auto c = g.Cell(nodes.voxel[i]);
    for (int a = 0; a < 3; ++a) {
      if (c[size_t(a)] + 1 >= d[size_t(a)]) continue;
      const int32_t j = nodes.node_of_voxel[size_t(int64_t(nodes.voxel[i]) + stride[a])];
      if (j >= 0) edges.emplace_back(int(i), j);
    }
  }
  // 2D edges: neighbouring pixels of one view whose nodes are close but not 6-adjacent; sorted, unique.
  std::vector<std::pair<int, int>> pairs;
  for (size_t r0 = 0; r0 < ev.rays.size();) {
    size_t r1 = r0;
    int w = 0, h = 0;
    for (; r1 < ev.rays.size() && ev.rays[r1].view == ev.rays[r0].view; ++r1) {
      w = std::max(w, ev.rays[r1].px + 1);
      h = std::max(h, ev.rays[r1].py + 1);
    }
    std::vector<int32_t> img(size_t(w) * h, -1);
    for (size_t r = r0; r < r1; ++r) img[size_t(ev.rays[r].py) * w + ev.rays[r].px] = vis[r];
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int k = 0; k < 2; ++k) {
          const int xx = x + (k == 0), yy = y + (k == 1);
          if (xx >= w || yy >= h) continue;
          const int32_t a = img[size_t(y) * w + x], b = img[size_t(yy) * w + xx];
          if (a < 0 || b < 0 || a == b) continue;
          const auto ca = g.Cell(nodes.voxel[size_t(a)]), cb = g.Cell(nodes.voxel[size_t(b)]);
          const int dx = ca[0] - cb[0], dy = ca[1] - cb[1], dz = ca[2] - cb[2];
          if (std::abs(dx) + std::abs(dy) + std::abs(dz) <= 1) continue;
          if (double(dx * dx + dy * dy + dz * dz) * g.resolution() * g.resolution() > std::pow(2.5 * g.resolution(), 2)) continue;
          pairs.emplace_back(std::min(a, b), std::max(a, b));
        }
    r0 = r1;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  EXPECT_GT(pairs.size(), size_t(0));
  ASSERT_EQ(p.edges.size(), edges.size() + pairs.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    ASSERT_EQ(p.edges[e].i, edges[e].first) << "edge " << e;
    ASSERT_EQ(p.edges[e].j, edges[e].second) << "edge " << e;
    ASSERT_GE(p.edges[e].type, kWPairwise3d);
    ASSERT_LT(p.edges[e].type, kWPairwise2d);
  }
  for (size_t e = 0; e < pairs.size(); ++e) {
    const VoxelCrfProblem::Edge& got = p.edges[edges.size() + e];
    ASSERT_EQ(got.i, pairs[e].first) << "2D edge " << e;
    ASSERT_EQ(got.j, pairs[e].second) << "2D edge " << e;
    ASSERT_EQ(got.type, kWPairwise2d);
  }
}

// The cabinet room mapped, rendered and classified by a stand-in per-view classifier that gives every pixel's
// true class the probability p_true and spreads the rest evenly over the other classes.
struct ClassifiedCabinetRoom {
  CabinetRoom room = MakeCabinetRoom();
  Scene scene = MeshScene(room.mesh);
  VoxelMap map = MapOf(scene);
  LabelLevel level = SecondLevel();
  VoxelCrfNodes nodes;
  VoxelEvidence ev;
  int K() const { return level.num_classes(); }
  VoxelCrfModel DefaultModel() const {
    std::vector<int> nyu40;
    for (const std::string& name : level.class_names) nyu40.push_back(name == "other" ? nyu40::kOtherProp : Nyu40IdByName(name));
    return VoxelCrfModel::Default(nyu40, level.class_names);
  }
};

std::unique_ptr<ClassifiedCabinetRoom> ClassifyCabinetRoom(float p_true) {
  auto r = std::make_unique<ClassifiedCabinetRoom>();
  const VoxelGrid& g = r->map.grid;
  const int K = r->K();
  r->nodes = SelectVoxelCrfNodes(g, r->map.floor_z, r->map.ceiling_z, VoxelEvidenceOptions{});
  EvidenceAccumulator acc(g, r->nodes, K, VoxelEvidenceOptions{});
  Result<ViewRenderer> renderer = ViewRenderer::Create(r->scene);
  EXPECT_TRUE(renderer.ok());
  if (!renderer.ok()) return r;
  ViewsOptions vo;
  vo.width = 160;
  vo.height = 120;
  vo.tilted_ring_deg = 40;  // Floor and ceiling near the viewpoints too.
  const std::vector<int32_t>& face_label = r->scene.mesh.face_attributes.at("label");
  Result<ViewSet> views = RenderViews(*renderer, r->map, vo, [&](const ViewRecord& rec, const RenderedView& view) {
    if (!rec.kept()) return Status::Ok();
    acc.AddDepthView(view);
    std::vector<float> probs(size_t(view.camera.width) * view.camera.height * K, (1.f - p_true) / float(K - 1));
    for (int y = 0; y < view.camera.height; ++y)
      for (int x = 0; x < view.camera.width; ++x)
        if (view.hit(x, y)) {
          const int cls = r->level.class_of_nyu40[size_t(face_label[size_t(view.primitive.at(x, y))])];
          probs[(size_t(y) * view.camera.width + x) * K + size_t(cls)] = p_true;
        }
    acc.AddClassifiedView(view, nullptr, probs);
    return Status::Ok();
  });
  EXPECT_TRUE(views.ok()) << views.status().message();
  r->ev = std::move(acc).Finish();
  return r;
}

TEST(VoxelCrf, PlaneCompletionLabelsTheWallBehindACabinetAsWall) {
  // Classification: the true class of each pixel with probability 0.7 (what a decent per-view classifier gives).
  const std::unique_ptr<ClassifiedCabinetRoom> cr = ClassifyCabinetRoom(0.7f);
  const VoxelMap& map = cr->map;
  const VoxelGrid& g = map.grid;
  const LabelLevel& level = cr->level;
  const VoxelCrfNodes& nodes = cr->nodes;
  const VoxelEvidence& ev = cr->ev;
  const VoxelCrfModel model = cr->DefaultModel();
  VoxelCrfResult result;
  ASSERT_TRUE(SolveVoxelCrf(g, nodes, ev, map.floor_z, map.ceiling_z, model, VoxelCrfOptions{}, &result).ok());
  // Energy never rises within an expansion sweep (the solver records one value per sweep).
  for (const auto& it : result.iterations)
    for (size_t s = 1; s < it.energy_per_sweep.size(); ++s) EXPECT_LE(it.energy_per_sweep[s], it.energy_per_sweep[s - 1] + 1e-6);
  const int wall = level.class_of_nyu40[nyu40::kWall] + 1;
  size_t behind = 0, behind_unknown = 0, behind_wall = 0, inside = 0, inside_occupied = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const auto c = g.Cell(nodes.voxel[i]);
    const V p = g.CellCenter(c[0], c[1], c[2]);
    if (CabinetRoom::BehindCabinet(p)) {
      ++behind;
      behind_unknown += nodes.initial_state[i] == uint8_t(VoxelState::kUnknown);
      behind_wall += result.labels[i] == wall;
    }
    if (CabinetRoom::InsideCabinet(p)) {
      ++inside;
      inside_occupied += result.labels[i] != 0;
    }
  }
  ASSERT_GT(behind, 200u);
  EXPECT_EQ(behind_unknown, behind) << "the scan must not see the wall behind the cabinet";
  EXPECT_GE(double(behind_wall), 0.9 * double(behind)) << behind_wall << " of " << behind << " hidden wall voxels labelled wall";
  EXPECT_LE(double(inside_occupied), 0.05 * double(inside)) << inside_occupied << " of " << inside << " cabinet-inside voxels filled";
  // The exports: completed voxels carry completed = 1 and the wall label.
  const SemanticMap sm = MakeSemanticMap(g, nodes, ev, result, model);
  size_t completed_wall = 0;
  for (const auto& r : sm.occupied) completed_wall += r.completed && r.label == nyu40::kWall && CabinetRoom::BehindCabinet(r.centre.cast<double>());
  EXPECT_EQ(completed_wall, behind_wall);
}

// Layout counts for K classes (wall 0, floor 1, cabinet 2, the rest never seen): sideways and normal-less
// cells 95 wall : 5 cabinet, upward cells all floor, downward cells all ceiling-less (empty).
std::vector<double> WallDominatedLayoutCounts(int K) {
  std::vector<double> counts(size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * size_t(K), 0.0);
  for (int h = 0; h < LayoutPrior::kHeightBins; ++h)
    for (int n = 0; n < LayoutPrior::kNormalBins; ++n) {
      double* c = &counts[(size_t(h) * LayoutPrior::kNormalBins + size_t(n)) * size_t(K)];
      if (n == 0 || n == 3) c[0] = 95, c[2] = 5;
      if (n == 1) c[1] = 100;
    }
  return counts;
}

TEST(LayoutPrior, RatioFormDividesOutTheClassFrequencies) {
  const int K = 4;
  const LayoutPrior prior = LayoutPrior::FromCounts(K, WallDominatedLayoutCounts(K));
  const int sideways = 3, up = 1;
  // Frequency form: wall is log(96 / 6) cheaper than cabinet on every vertical surface.
  EXPECT_NEAR(prior.Cost(5, sideways, 2) - prior.Cost(5, sideways, 0), std::log(96.0 / 6.0), 1e-5);
  // Ratio form without shrinkage: the sideways cells hold wall and cabinet in the same proportion as the whole
  // room does, so neither is favoured; floor and the never-seen class cost more; the cheapest class costs
  // what it costs in the frequency form.
  const std::vector<float> r0 = prior.RatioCosts(0.0, 1.0);
  ASSERT_EQ(r0.size(), prior.neg_log_p.size());
  auto at = [&](const std::vector<float>& r, int h, int n, int k) { return r[(size_t(h) * LayoutPrior::kNormalBins + size_t(n)) * K + size_t(k)]; };
  EXPECT_NEAR(at(r0, 5, sideways, 0), at(r0, 5, sideways, 2), 1e-5);
  EXPECT_GT(at(r0, 5, sideways, 1), at(r0, 5, sideways, 0) + 5.0);
  EXPECT_NEAR(at(r0, 5, sideways, 0), prior.Cost(5, sideways, 0), 1e-5);
  EXPECT_NEAR(at(r0, 0, up, 1), prior.Cost(0, up, 1), 1e-5);
  // A cell where the cabinet is over-represented (50 : 50 against 95 : 5 overall) favours it by
  // log((0.5 / 0.0475) / (0.5 / 0.9025)) - a share computed over all cells.
  std::vector<double> counts = WallDominatedLayoutCounts(K);
  double* cell = &counts[(size_t(7) * LayoutPrior::kNormalBins + sideways) * K];
  cell[0] = 50, cell[2] = 50;
  const LayoutPrior skewed = LayoutPrior::FromCounts(K, counts);
  double wall = 0, cab = 0, all = 0;
  for (size_t i = 0; i < counts.size(); ++i) wall += i % K == 0 ? counts[i] : 0, cab += i % K == 2 ? counts[i] : 0, all += counts[i];
  const std::vector<float> r1 = skewed.RatioCosts(0.0, 1.0);
  EXPECT_NEAR(at(r1, 7, sideways, 0) - at(r1, 7, sideways, 2), std::log((0.5 / (cab / all)) / (0.5 / (wall / all))), 1e-4);
  // Powers between 0 and 1 temper the division: the cabinet's advantage is linear in the power (without
  // pseudo-voxels power 0 is the unsmoothed frequency form).
  const std::vector<float> half = skewed.RatioCosts(0.0, 0.5), none = skewed.RatioCosts(0.0, 0.0);
  const double d1 = at(r1, 7, sideways, 0) - at(r1, 7, sideways, 2), d0 = at(none, 7, sideways, 0) - at(none, 7, sideways, 2);
  EXPECT_NEAR(d0, 0.0, 1e-5);  // 50 : 50 in that cell.
  EXPECT_NEAR(at(half, 7, sideways, 0) - at(half, 7, sideways, 2), 0.5 * (d0 + d1), 1e-4);
  // Pseudo-voxels shrink a cell towards the overall shares: with m = 1e6 the 100 voxels of the skewed cell
  // barely count.
  const std::vector<float> r2 = skewed.RatioCosts(1e6, 1.0);
  EXPECT_LT(std::fabs(at(r2, 7, sideways, 0) - at(r2, 7, sideways, 2)), 0.01);
  // Without counts there is no ratio form.
  LayoutPrior bare = prior;
  bare.counts.clear();
  EXPECT_TRUE(bare.RatioCosts(200, 1.0).empty());
}

TEST(LayoutPrior, CountsAreRecoveredFromModelFilesThatDoNotHoldThem) {
  const int K = 5;
  std::mt19937_64 rng(11);
  std::vector<double> counts(size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * K, 0.0);
  for (size_t c = 0; c < counts.size() / K; ++c)
    for (int k = 1; k < K; ++k) counts[c * K + size_t(k)] = double(rng() % 5000);  // Class 0 never seen.
  for (int k = 0; k < K; ++k) counts[size_t(k)] = 0;                                // One empty cell.
  testing::ScratchDir dir("layout_counts");
  VoxelCrfModel m = VoxelCrfModel::Default({1, 2, 3, 4, 40}, {"wall", "floor", "cabinet", "bed", "other"});
  m.layout = LayoutPrior::FromCounts(K, counts);
  ASSERT_TRUE(m.Save(dir.File("with.txt")).ok());
  m.layout.counts.clear();  // As files written before the counts were saved.
  ASSERT_TRUE(m.Save(dir.File("without.txt")).ok());
  EXPECT_EQ(testing::ReadText(dir.File("without.txt")).find("layout_counts"), std::string::npos);
  for (const char* name : {"with.txt", "without.txt"}) {
    Result<VoxelCrfModel> back = VoxelCrfModel::Load(dir.File(name));
    ASSERT_TRUE(back.ok()) << back.status().message();
    EXPECT_EQ(back->layout.counts, counts) << name;
  }
  // A cell in which every class was seen gives no way back: the counts stay unknown.
  std::vector<double> seen(counts.size());
  for (size_t i = 0; i < seen.size(); ++i) seen[i] = double(std::vector<int>{2, 3, 7, 11, 20}[i % K]);
  LayoutPrior full = LayoutPrior::FromCounts(K, seen);
  full.counts.clear();
  EXPECT_FALSE(full.RecoverCounts());
  EXPECT_TRUE(full.counts.empty());
  // The shipped models were written before the counts were saved: theirs come back whole, and smoothing
  // them again gives the file's prior.
  for (const char* shipped : {"voxel_crf.txt", "voxel_crf_cloud.txt"}) {
    Result<VoxelCrfModel> s = VoxelCrfModel::Load(std::string(SEMVOX_SOURCE_DIR) + "/models/" + shipped);
    ASSERT_TRUE(s.ok()) << s.status().message();
    ASSERT_EQ(s->layout.counts.size(), s->layout.neg_log_p.size()) << shipped;
    const LayoutPrior again = LayoutPrior::FromCounts(s->num_classes(), s->layout.counts);
    for (size_t i = 0; i < again.neg_log_p.size(); ++i) ASSERT_NEAR(again.neg_log_p[i], s->layout.neg_log_p[i], 1e-5) << shipped << " " << i;
  }
}

// A per-view classifier that is right with probability 0.6 and a layout prior in which walls are 95 % of
// every vertical surface. The classifier's posterior already carries its class frequencies; multiplied by
// the frequency form of the prior, the wall's share is counted twice and the cabinet's front is lost (wall or emptied).
// The ratio form keeps it a cabinet and the walls walls.
TEST(VoxelCrf, RatioLayoutPriorKeepsACabinetFrontThatTheFrequencyFormLoses) {
  const std::unique_ptr<ClassifiedCabinetRoom> cr = ClassifyCabinetRoom(0.6f);
  const VoxelGrid& g = cr->map.grid;
  VoxelCrfModel model = cr->DefaultModel();
  const int wall = cr->level.class_of_nyu40[nyu40::kWall], floor = cr->level.class_of_nyu40[nyu40::kFloor];
  const int cab = cr->level.class_of_nyu40[nyu40::kCabinet];
  std::vector<double> counts(size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * size_t(cr->K()), 0.0);
  const std::vector<double> three = WallDominatedLayoutCounts(3);
  for (size_t c = 0; c < counts.size() / size_t(cr->K()); ++c) {
    counts[c * size_t(cr->K()) + size_t(wall)] = three[c * 3 + 0];
    counts[c * size_t(cr->K()) + size_t(floor)] = three[c * 3 + 1];
    counts[c * size_t(cr->K()) + size_t(cab)] = three[c * 3 + 2];
  }
  model.layout = LayoutPrior::FromCounts(cr->K(), counts);
  model.w[kWLayout] = 2.0;
  auto solve = [&](double power, double* front_cabinet, double* wall_wall) {
    VoxelCrfOptions o;
    o.layout_frequency_power = power;
    VoxelCrfResult result;
    ASSERT_TRUE(SolveVoxelCrf(g, cr->nodes, cr->ev, cr->map.floor_z, cr->map.ceiling_z, model, o, &result).ok());
    size_t front = 0, front_cab = 0, walls = 0, walls_wall = 0;
    for (size_t i = 0; i < cr->nodes.size(); ++i) {
      const auto c = g.Cell(cr->nodes.voxel[i]);
      const V p = g.CellCenter(c[0], c[1], c[2]);
      if (cr->nodes.initial_state[i] != uint8_t(VoxelState::kOccupied)) continue;  // The scanned surface's voxels.
      if (p.y() > 0.45 && p.y() < 0.55 && p.x() > 1.6 && p.x() < 2.4 && p.z() > 0.2 && p.z() < 1.4) {
        ++front;
        front_cab += result.labels[i] == cab + 1;
      }
      if (p.y() > 2.95 && p.y() < 3.05 && p.x() > 0.2 && p.x() < 3.8 && p.z() > 0.2 && p.z() < 2.3) {  // North wall.
        ++walls;
        walls_wall += result.labels[i] == wall + 1;
      }
    }
    ASSERT_GT(front, 100u);
    ASSERT_GT(walls, 500u);
    *front_cabinet = double(front_cab) / double(front);
    *wall_wall = double(walls_wall) / double(walls);
  };
  double freq_front = 0, freq_wall = 0, ratio_front = 0, ratio_wall = 0;
  solve(0.0, &freq_front, &freq_wall);
  solve(1.0, &ratio_front, &ratio_wall);
  EXPECT_LT(freq_front, 0.1) << "frequency form: share of the cabinet's front labelled cabinet (the rest is wall or emptied)";
  EXPECT_GT(ratio_front, 0.9) << "ratio form: share of the cabinet's front labelled cabinet";
  EXPECT_GT(freq_wall, 0.95);
  EXPECT_GT(ratio_wall, 0.95);
  // A model that does not trust the per-view classifiers (the point-cloud model) keeps the frequency form.
  model.w[kWAppearance] = 0.5 * VoxelCrfOptions::kEvidenceWeight;
  VoxelCrfOptions ratio;
  ratio.layout_frequency_power = 1;
  const VoxelCrfProblem a = BuildVoxelCrfProblem(g, cr->nodes, cr->ev, cr->map.floor_z, cr->map.ceiling_z, model, {}, ratio, std::vector<int32_t>(cr->ev.rays.size(), -1));
  VoxelCrfOptions freq;
  freq.layout_frequency_power = 0;
  const VoxelCrfProblem b = BuildVoxelCrfProblem(g, cr->nodes, cr->ev, cr->map.floor_z, cr->map.ceiling_z, model, {}, freq, std::vector<int32_t>(cr->ev.rays.size(), -1));
  EXPECT_EQ(a.f_layout, b.f_layout);
}

// The cabinet room as a sparse real scan delivers it: points scattered over the surfaces at random, about
// one per 5 cm voxel face (the ScanNet studio holds 1.25 points per occupied voxel), no normals, no colours.
Scene SparseCloudOf(const Mesh& m, double per_m2, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Scene s;
  s.format = "test";
  for (const auto& f : m.faces) {
    const V a = m.vertices[size_t(f[0])].cast<double>(), b = m.vertices[size_t(f[1])].cast<double>(), c = m.vertices[size_t(f[2])].cast<double>();
    const double expected = 0.5 * (b - a).cross(c - a).norm() * per_m2;
    const int n = int(expected) + (u01(rng) < expected - std::floor(expected) ? 1 : 0);
    for (int k = 0; k < n; ++k) {
      double r1 = u01(rng), r2 = u01(rng);
      if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
      s.cloud.points.push_back((a + r1 * (b - a) + r2 * (c - a)).cast<float>());
    }
  }
  return s;
}

// With an uninformative classifier (a real scan's views say little), the point-cloud Voxel-CRF weights empty
// voxels the scan has points in; keep_scan_points bars that, and only that: every voxel holding a point
// stays occupied, and the map records exactly the voxels holding points.
// The evidence of 160 x 120 views of `scene`: their depth, and a classifier that knows nothing (uniform over
// the K classes).
VoxelEvidence UninformedEvidence(const Scene& scene, const VoxelMap& map, const VoxelCrfNodes& nodes, int K) {
  EvidenceAccumulator acc(map.grid, nodes, K, VoxelEvidenceOptions{});
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene);
  EXPECT_TRUE(renderer.ok()) << renderer.status().message();
  if (!renderer.ok()) return std::move(acc).Finish();
  ViewsOptions vo;
  vo.width = 160;
  vo.height = 120;
  Result<ViewSet> views = RenderViews(*renderer, map, vo, [&](const ViewRecord& r, const RenderedView& view) {
    if (!r.kept()) return Status::Ok();
    acc.AddDepthView(view);
    acc.AddClassifiedView(view, nullptr, std::vector<float>(size_t(view.camera.width) * view.camera.height * K, 1.f / float(K)));
    return Status::Ok();
  });
  EXPECT_TRUE(views.ok()) << views.status().message();
  return std::move(acc).Finish();
}

// How many of the nodes marked `holds_point` the Voxel-CRF leaves occupied, with or without keep_scan_points.
size_t OccupiedMarkedNodes(const VoxelMap& map, const VoxelCrfNodes& nodes, const VoxelEvidence& ev, const VoxelCrfModel& model,
                           bool keep) {
  VoxelCrfOptions o;
  o.keep_scan_points = keep;
  VoxelCrfResult result;
  EXPECT_TRUE(SolveVoxelCrf(map.grid, nodes, ev, map.floor_z, map.ceiling_z, model, o, &result).ok());
  size_t n = 0;
  for (size_t i = 0; i < nodes.size(); ++i) n += nodes.holds_point[i] && result.labels[i] != 0;
  return n;
}

TEST(VoxelCrf, SparseCloudKeepsEveryVoxelThatHoldsAPoint) {
  const Scene scene = SparseCloudOf(MakeCabinetRoom().mesh, 400.0, 3);
  const VoxelMap map = MapOf(scene);
  const VoxelGrid& g = map.grid;
  {  // point_voxels: the distinct cells of the points, ascending.
    std::vector<uint32_t> cells;
    for (const auto& p : scene.cloud.points) {
      const auto c = g.CellOf(p.cast<double>());
      if (g.Contains(c[0], c[1], c[2])) cells.push_back(uint32_t(g.Index(c[0], c[1], c[2])));
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    EXPECT_EQ(map.point_voxels, cells);
    for (uint32_t v : cells) EXPECT_EQ(g.state(v), VoxelState::kOccupied);
  }
  const LabelLevel level = SecondLevel();
  const int K = level.num_classes();
  VoxelCrfNodes nodes = SelectVoxelCrfNodes(g, map.floor_z, map.ceiling_z, VoxelEvidenceOptions{});
  MarkPointNodes(map.point_voxels, &nodes);
  const size_t holding = size_t(std::count(nodes.holds_point.begin(), nodes.holds_point.end(), uint8_t(1)));
  EXPECT_EQ(holding, map.point_voxels.size());  // Every occupied voxel is a node.
  ASSERT_GT(holding, 2000u);
  const VoxelEvidence ev = UninformedEvidence(scene, map, nodes, K);
  Result<VoxelCrfModel> model = VoxelCrfModel::Load(std::string(SEMVOX_SOURCE_DIR) + "/models/voxel_crf_cloud.txt");
  ASSERT_TRUE(model.ok()) << model.status().message();
  ASSERT_EQ(model->num_classes(), K);
  EXPECT_EQ(OccupiedMarkedNodes(map, nodes, ev, *model, true), holding);
  const size_t without = OccupiedMarkedNodes(map, nodes, ev, *model, false);
  std::printf("voxels holding points: %zu; occupied without keep_scan_points: %zu\n", holding, without);
  EXPECT_LT(double(without), 0.9 * double(holding)) << without << " of " << holding << " point voxels occupied without the option";
}

// A mesh's surface is exact: every voxel it passes through is kept occupied, as a cloud's point voxels are.
// Before 2026-12-05 meshes had no such constraint, and where the per-view evidence and an object segment
// disagreed the Voxel-CRF emptied whole counters. Here a per-voxel cost of being occupied (the bias weight
// raised to 5) makes emptying cheap: without the constraint most surface voxels go, with it none.
TEST(VoxelCrf, MeshSurfaceVoxelsStayOccupied) {
  const Scene scene = MeshScene(MakeCabinetRoom().mesh);
  const VoxelMap map = MapOf(scene);
  EXPECT_TRUE(map.exact_surface);
  EXPECT_TRUE(map.point_voxels.empty());
  EXPECT_FALSE(MapOf(SparseCloudOf(MakeCabinetRoom().mesh, 400.0, 3)).exact_surface);
  const VoxelGrid& g = map.grid;
  const LabelLevel level = SecondLevel();
  const int K = level.num_classes();
  VoxelCrfNodes nodes = SelectVoxelCrfNodes(g, map.floor_z, map.ceiling_z, VoxelEvidenceOptions{});
  MarkSurfaceNodes(&nodes);
  ASSERT_EQ(nodes.holds_point.size(), nodes.size());
  size_t surface = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const bool occupied = g.state(nodes.voxel[i]) == VoxelState::kOccupied;
    ASSERT_EQ(nodes.holds_point[i] != 0, occupied) << i;
    surface += occupied;
  }
  ASSERT_GT(surface, 2000u);
  const VoxelEvidence ev = UninformedEvidence(scene, map, nodes, K);
  Result<VoxelCrfModel> model = VoxelCrfModel::Load(std::string(SEMVOX_SOURCE_DIR) + "/models/voxel_crf.txt");
  ASSERT_TRUE(model.ok()) << model.status().message();
  ASSERT_EQ(model->num_classes(), K);
  model->w[kWOccupiedBias] = 5.0;
  EXPECT_EQ(OccupiedMarkedNodes(map, nodes, ev, *model, true), surface);
  const size_t without = OccupiedMarkedNodes(map, nodes, ev, *model, false);
  std::printf("surface voxels: %zu; occupied without the constraint: %zu\n", surface, without);
  EXPECT_LT(double(without), 0.5 * double(surface));
}

// The top view shows each column's highest voxel in the band; with a confidence floor it passes over the
// voxels whose label the Voxel-CRF barely preferred.
TEST(SemanticExports, TopViewPassesOverLabelsBelowTheConfidenceFloor) {
  const VoxelGrid grid(0.05, {32768, 32768, 32768}, {2, 1, 20});
  SemanticMap m;
  auto add = [&](int x, int z, uint16_t label, float confidence) {
    SemanticVoxelRecord r;
    r.voxel = uint32_t(grid.Index(x, 0, z));
    r.centre = grid.CellCenter(x, 0, z).cast<float>();
    r.label = label;
    r.confidence = confidence;
    m.occupied.push_back(r);
  };
  const double floor_z = grid.CellCenter(0, 0, 0).z() - 0.025;
  add(0, 8, nyu40::kTable, 0.9f);     // 0.4 m above the floor.
  add(0, 14, nyu40::kCounter, 0.2f);  // 0.7 m: on top, barely preferred.
  add(1, 10, nyu40::kBed, 0.3f);
  const ImageU16 all = SemanticTopView(m, grid, floor_z, 0.1, 2.0);
  EXPECT_EQ(all.at(0, 0), nyu40::kCounter);
  EXPECT_EQ(all.at(1, 0), nyu40::kBed);
  const ImageU16 sure = SemanticTopView(m, grid, floor_z, 0.1, 2.0, 0.35);
  EXPECT_EQ(sure.at(0, 0), nyu40::kTable);
  EXPECT_EQ(sure.at(1, 0), 0);
}

TEST(SemanticExports, VoxelsPlyAndSemanticOctreeRoundTrip) {
  testing::ScratchDir dir("voxelcrf");
  SemanticMap m;
  for (int k = 0; k < 5; ++k) {
    SemanticVoxelRecord r;
    r.voxel = uint32_t(k);
    r.centre = Eigen::Vector3f(0.025f + 0.05f * k, 0.025f, 1.025f);
    r.rgb = {uint8_t(10 * k), 20, 30};
    r.label = uint16_t(k + 1);
    r.confidence = 0.5f + 0.1f * k;
    r.room = k - 1;
    r.completed = uint8_t(k % 2);
    m.occupied.push_back(r);
  }
  const std::string ply = dir.File("voxels.ply");
  ASSERT_TRUE(WriteVoxelsPly(m, ply).ok());
  Result<PlyData> data = ReadPly(ply);
  ASSERT_TRUE(data.ok());
  const PlyElement* v = data->Find("vertex");
  ASSERT_NE(v, nullptr);
  ASSERT_EQ(v->count, 5u);
  const std::pair<const char*, PlyType> expected[] = {{"x", PlyType::kFloat32}, {"y", PlyType::kFloat32}, {"z", PlyType::kFloat32},
                                                      {"red", PlyType::kUInt8}, {"green", PlyType::kUInt8}, {"blue", PlyType::kUInt8},
                                                      {"label", PlyType::kUInt16}, {"confidence", PlyType::kFloat32},
                                                      {"room", PlyType::kInt32}, {"completed", PlyType::kUInt8}};
  ASSERT_EQ(v->properties.size(), std::size(expected));
  for (size_t i = 0; i < std::size(expected); ++i) {
    EXPECT_EQ(v->properties[i].name, expected[i].first);
    EXPECT_EQ(v->properties[i].type, expected[i].second);
  }
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(v->Find("label")->values[size_t(k)], k + 1);
    EXPECT_EQ(v->Find("room")->values[size_t(k)], k - 1);
    EXPECT_NEAR(v->Find("confidence")->values[size_t(k)], 0.5 + 0.1 * k, 1e-6);
  }
  // map.ot: occupied voxels with labels, free voxels with label 0; pruned free blocks come back expanded.
  std::vector<SemanticVoxel> voxels;
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 8; ++z) voxels.push_back({VoxelKey{uint16_t(32768 + x), uint16_t(32768 + y), uint16_t(32768 + z)}, false, 0, 0.f});
  voxels.push_back({VoxelKey{32800, 32768, 32768}, true, 7, 0.75f});
  voxels.push_back({VoxelKey{32801, 32768, 32768}, true, 1, 0.25f});
  const std::string ot = dir.File("map.ot");
  ASSERT_TRUE(WriteSemanticOctree(voxels, 0.05, ot).ok());
  double res = 0;
  Result<std::vector<SemanticVoxel>> back = ReadSemanticOctree(ot, &res);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_DOUBLE_EQ(res, 0.05);
  ASSERT_EQ(back->size(), voxels.size());
  std::sort(voxels.begin(), voxels.end(), [](const SemanticVoxel& a, const SemanticVoxel& b) { return a.key.Pack() < b.key.Pack(); });
  for (size_t i = 0; i < voxels.size(); ++i) {
    EXPECT_EQ((*back)[i].key.Pack(), voxels[i].key.Pack());
    EXPECT_EQ((*back)[i].occupied, voxels[i].occupied);
    EXPECT_EQ((*back)[i].label, voxels[i].label);
    EXPECT_FLOAT_EQ((*back)[i].confidence, voxels[i].confidence);
  }
  // A plain OctoMap .bt is not a semantic tree: one clear error.
  const std::string bt = dir.File("plain.bt");
  VoxelGrid grid(0.05, {32768, 32768, 32768}, {2, 2, 2});
  grid.set_state(0, VoxelState::kOccupied);
  ASSERT_TRUE(WriteOctomapBinary(grid, bt).ok());
  EXPECT_FALSE(ReadSemanticOctree(bt, &res).ok());
}

TEST(VoxelCrfModel, SavesAndLoadsAndRejectsBadFiles) {
  testing::ScratchDir dir("voxelcrf");
  VoxelCrfModel m = VoxelCrfModel::Default({1, 2, 40}, {"wall", "floor", "other"});
  std::vector<double> counts(size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * 3, 1.0);
  counts[0] = 50;
  m.layout = LayoutPrior::FromCounts(3, counts);
  m.w[kWPlane] = 2.5;
  const std::string path = dir.File("voxel_crf.txt");
  ASSERT_TRUE(m.Save(path).ok());
  Result<VoxelCrfModel> back = VoxelCrfModel::Load(path);
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->nyu40_of_class, m.nyu40_of_class);
  EXPECT_DOUBLE_EQ(back->w[kWPlane], 2.5);
  EXPECT_NEAR(back->layout.Cost(0, 0, 0), m.layout.Cost(0, 0, 0), 1e-5);
  EXPECT_LT(back->layout.Cost(0, 0, 0), back->layout.Cost(0, 0, 1));
  testing::WriteText(path, "weights 3 1 2 3\n");
  Result<VoxelCrfModel> bad = VoxelCrfModel::Load(path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find(path), std::string::npos);
}

TEST(Planes, ConvexHullOfASquareWithInnerPoints) {
  std::vector<Eigen::Vector2d> pts = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.2, 0.7}, {1, 0.5}};
  const auto h = ConvexHull2D(pts);
  EXPECT_EQ(h.size(), 4u);
}

}  // namespace
}  // namespace semvox
