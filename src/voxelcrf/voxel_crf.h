// The Voxel-CRF (Kim, Kohli & Savarese, "3D Scene Understanding by Voxel-CRF", ICCV 2013): a labelled,
// completed voxel map from the evidence of many views.
//
//   VoxelCrfNodes nodes = SelectVoxelCrfNodes(...);  VoxelEvidence ev = ...;        (voxel_evidence.h)
//   Result<VoxelCrfModel> model = VoxelCrfModel::Load("models/voxel_crf.txt");
//   VoxelCrfResult result;
//   Status st = SolveVoxelCrf(grid, nodes, ev, floor_z, ceiling_z, *model, VoxelCrfOptions{}, &result);
//
// Labels. Each node takes one label l in {0 = empty, 1..K}: the occupancy o_i and semantic label s_i of the
// paper in one variable (o_i = 0 iff l = 0); class k >= 1 is the per-view classifier's class k - 1.
//
// Energy (Eq. 1), with visibility V fixed (Alg. 1 step 2), linear in the weights w:
//   unary, occupied (Eq. 3):  w1 v_i (-log P(s_i|O)) + w2 (-log F_i) + w3 (-log rho_i)       observed voxels
//                             + w_unseen [unknown in the map] + w_free [free in the map] + w_bias
//                             + w_layout (-log P(s_i | height, normal))
//   unary, empty (Eq. 4):     w4 (-log(1 - F_i)) + w5 (-log(1 - rho_i))                     observed voxels
//                             + w_surface [occupied in the map]
// (the map's own states are the scan's evidence for voxels no rendered view observes: surfaces inside
// thick walls, tops of tall furniture)
//   pairwise, 3D (Eq. 5-8):   w(s_ij, case, c_ij) [l_i != l_j] over 6-adjacent nodes; s_ij vertical or
//                             horizontal; case both visible (with colour-difference cluster c_ij of 3),
//                             one visible, none visible
//   pairwise, 2D:             w_2d [l_i != l_j] between the visible voxels of neighbouring rays of one view
//                             that are close in 3D (within 2.5 voxels) but not 6-adjacent; pairs across an
//                             occlusion boundary (farther apart) get no edge, i.e. no smoothing
//   higher order (Sec. 4.3):  Robust P^n over each plane's convex-hull nodes and each object segment:
//                             w_g min(Q, min_{l >= 1} N_l), Q = truncation x clique size (never rewards
//                             "all empty")
// F_i, rho_i: voxel_evidence.h. Logs are clipped at -log(1e-3). The layout prior P(s | height, normal) is a
// histogram learned with the weights: the "room layout" prior the paper lists among higher-level cues
// (Sec. 4.3); it labels surfaces no classified view sees (ceilings).
//
// Inference (Alg. 1): V_0 from the map (the first occupied voxel along each classified-view ray); then per
// iteration: build the energy for V_t, minimise it by alpha-expansion (crf/solvers.h, own Boykov-Kolmogorov
// max-flow, Robust P^n with auxiliary nodes), recompute V_{t+1} from the new labels by walking every ray to
// its first voxel labelled occupied (Eq. 9: exactly one visible voxel per ray), and stop after
// max_iterations or when V (almost) no longer changes (visibility_tolerance).
//
// Learning (Sec. 5.2): structural SVM by stochastic subgradient descent (voxel_crf_learning.h).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>
#include "core/option_table.h"
#include "core/status.h"
#include "core/voxel_grid.h"
#include "crf/energy.h"
#include "crf/solvers.h"
#include "voxelcrf/planes.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {

// Index of each weight in VoxelCrfWeights::w.
enum VoxelCrfWeight : int {
  kWAppearance = 0,   // w1^u
  kWDepthOccupied,    // w2^u
  kWDensityOccupied,  // w3^u
  kWDepthEmpty,       // w4^u
  kWDensityEmpty,     // w5^u
  kWUnseenOccupied,   // occupied, where the map never saw the voxel (unknown): the cost of completion
  kWOccupiedBias,     // per occupied voxel (may be negative)
  kWLayout,           // -log P(s | height, normal)
  kWMapOccupiedEmpty, // empty, where the map holds the voxel occupied (the scan's surface passes through it)
  kWMapFreeOccupied,  // occupied, where the map holds the voxel free (a scanner ray passed through it)
  kWPairwise3d,       // 10 weights: [vertical, horizontal] x [vv cluster 0, 1, 2, visible-hidden, hidden-hidden]
  kWPairwise2d = kWPairwise3d + 10,
  kWPlane,
  kWObject,
  kWSegment,          // -log P(class | shape) of the object segment holding the voxel (objects/object_segments.h)
  kNumVoxelCrfWeights
};

// P(s | height bin, normal bin): heights in 0.1 m bins counted from the floor in the lower half of the
// room and from the ceiling in the upper half (15 bins each way); normals up, down, sideways or none.
struct LayoutPrior {
  static constexpr int kHeightBins = 30, kNormalBins = 4;
  int num_classes = 0;
  std::vector<float> neg_log_p;  // [(height_bin * kNormalBins + normal_bin) * K + class]; empty = uniform.
  // The training voxels behind neg_log_p, same layout (empty when unknown). Model files written before
  // 2026-12-04 hold only neg_log_p; Load recovers the counts from it (RecoverCounts).
  std::vector<double> counts;
  static int HeightBin(double z, double floor_z, double ceiling_z);
  static int NormalBin(const Eigen::Vector3f& normal);  // 0 none, 1 up, 2 down, 3 sideways
  float Cost(int height_bin, int normal_bin, int cls) const {
    return neg_log_p.empty() ? 0.f : neg_log_p[(size_t(height_bin) * kNormalBins + size_t(normal_bin)) * size_t(num_classes) + size_t(cls)];
  }
  // From counts (same layout as neg_log_p), with add-one smoothing.
  static LayoutPrior FromCounts(int num_classes, const std::vector<double>& counts);
  // Inverts the add-one smoothing: in a cell with n voxels, p_k = (n_k + 1) / (n + K), so a class never seen
  // there has the cell's smallest p and n + K = 1 / min_k p. Exact (to the file's 9 digits) when every cell
  // has a class it never saw, as both shipped models do (22 classes, 120 cells); false and counts left empty
  // when a non-uniform cell has none, or the recovered counts are not whole numbers within 0.05.
  bool RecoverCounts();
  // The prior divided by a power of the class frequencies, for voxels whose label evidence is already a
  // classifier's posterior (which carries the class frequencies of its own training set):
  // -log(P~(s | cell) / P(s)^power), with P(s) the classes' share over all cells and
  // P~(s | cell) = (n_s + m P(s)) / (n + m), the cell's frequencies shrunk towards P(s) by m pseudo-voxels (a
  // sparsely filled cell says little). power 1 is the ratio P(s | cell) / P(s), which no longer prefers a
  // class for being common; between 0 and 1 the preference is tempered. Each cell is then shifted so that its
  // cheapest class costs what it costs in neg_log_p: the occupied-versus-empty balance stays as learned.
  // Empty when counts are unknown.
  std::vector<float> RatioCosts(double pseudo_count, double power) const;
};

struct VoxelCrfModel {
  std::array<double, kNumVoxelCrfWeights> w{};
  LayoutPrior layout;
  std::vector<int> nyu40_of_class;  // Per classifier class (K): the NYU40 id written for it.
  std::vector<std::string> class_names;
  int num_classes() const { return int(nyu40_of_class.size()); }
  // Hand-set weights for a model that has not been trained (tests; `semvox train` learns them).
  static VoxelCrfModel Default(std::vector<int> nyu40_of_class, std::vector<std::string> class_names);
  // Text file: "weights" line, "classes" lines, "layout" counts. Errors name file and line.
  Status Save(const std::string& path) const;
  static Result<VoxelCrfModel> Load(const std::string& path);
};

struct VoxelCrfOptions {
  int max_iterations = 5;
  double visibility_tolerance = 0.005;
  double visibility_min_progress = 0.25;  // For a visibility that oscillates instead of settling.
  bool use_pairwise = true;          // U+PW (false: U only).
  bool use_higher_order = true;      // U+PW+G (planes and objects).
  double plane_truncation = 0.25;
  double object_truncation = 0.25;
  int min_object_voxels = 20;
  // Voxels that hold a point of the input cloud (VoxelCrfNodes::holds_point): the scan saw a surface there;
  // without this a sparse real cloud (one point per voxel or fewer) loses about half of its surface voxels,
  // furniture first, because its depth and density evidence is weak. Disc-splat voxels without a point may
  // still be emptied. A mesh's surface voxels are kept the same way (MarkSurfaceNodes): without it, where the
  // per-view evidence and the object segment disagree (a counter the views call counter and its shape cabinet),
  // emptying the object was the cheapest answer, and whole counters and basins left the top view.
  bool keep_scan_points = true;
  // The layout prior P(s | height, normal) holds the classes' frequencies: walls are most of every vertical
  // surface at every height. When the labels come from the per-view classifiers (the model's appearance
  // weight at least kEvidenceWeight: the mesh model), whose posteriors carry their own class frequencies,
  // multiplying the two counts the frequencies twice and turns furniture standing against a wall into wall.
  // The prior is then divided by P(s)^layout_frequency_power on every node (LayoutPrior::RatioCosts; 0: as
  // learned). A model whose labels come from the layout itself and the object segments (the point-cloud
  // model, appearance weight ~0) keeps the prior as learned: its walls and floors have no other evidence
  // (docs/voxelcrf.md: measured both ways). Off by default: at 1 the generated apartments' mean recall
  // rises 0.25 -> 0.32, but on apartments built on real plans the per-view classifiers give plain walls
  // object and window evidence that only the wall's frequency outweighs (visible-voxel accuracy 0.81 -> 0.64).
  double layout_frequency_power = 0;
  double layout_pseudo_count = 200;  // m of LayoutPrior::RatioCosts, voxels.
  static constexpr double kEvidenceWeight = 0.01;
  PlaneDetectionOptions planes;
  // One alpha-expansion sweep over the labels per iteration: sweeps after the first lower the Voxel-CRF energy
  // by 1e-4 - 1e-7 of |E| on generated apartments (the 91 m2 flat of seed 106: the first sweep 6e-2, the second
  // 2e-4) at about half the solver's time, and the next iteration of Alg. 1 starts from these labels. Seven
  // generated validation runs: labels as good on average (docs/speed.md, thirteenth session).
  // min_sweep_improvement stops earlier when max_sweeps is raised.
  int max_sweeps = 1;
  // Iterations after the first re-solve only the nodes whose terms changed with the visibility (unary
  // features, incident edges, cliques) and the nodes within reiterate_rings CRF edges of them; the others keep
  // their labels (-1: every node, a full re-solve).
  int reiterate_rings = 2;
  AlphaExpansionOptions solver = [] {
    AlphaExpansionOptions o;
    o.min_sweep_improvement = 1e-3;
    return o;
  }();

  // The fields users set (section `semantic`): meaning, unit and range.
  static const OptionTable<VoxelCrfOptions>& Options() {
    using O = VoxelCrfOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        {
            OptionNumber(&O::max_iterations, "max_iterations", 1, 50, "", "Voxel-CRF iterations (Alg. 1) at most"),
            OptionNumber(&O::visibility_tolerance, "visibility_tolerance", 0, 1, "",
                         "Alg. 1 stops once fewer than this fraction of rays change their visible voxel"),
            OptionNumber(&O::visibility_min_progress, "visibility_min_progress", 0, 1, "",
                         "Alg. 1 also stops when an iteration moves more than (1 - this) times the rays the previous one moved"),
            OptionNumber(&O::max_sweeps, "max_sweeps", 1, 100, "", "alpha-expansion sweeps over all labels per iteration at most"),
            OptionNumber(&O::reiterate_rings, "reiterate_rings", -1, 1000, "",
                         "iterations after the first re-solve only the voxels whose terms the new visibility changed "
                         "and those within this many CRF edges of them (-1: every voxel)"),
            OptionNumber(&O::plane_truncation, "plane_truncation", 0.001, 0.5, "",
                         "Robust P^n truncation Q of plane cliques, fraction of the clique"),
            OptionNumber(&O::object_truncation, "object_truncation", 0.001, 0.5, "",
                         "Robust P^n truncation Q of object cliques, fraction of the clique"),
            OptionNumber(&O::min_object_voxels, "min_object_voxels", 2, 1000000, "voxels",
                         "smallest object segment with a clique"),
            OptionSwitch(&O::keep_scan_points, "keep_scan_points",
                         "voxels holding an input point (point clouds) or crossed by the input mesh's surface (meshes, "
                         "since 2026-12-05) stay occupied: the Voxel-CRF labels them but does not empty them"),
            OptionNumber(&O::layout_frequency_power, "layout_frequency_power", 0, 1, "",
                         "when the Voxel-CRF model trusts the per-view classifiers (the mesh model), the layout prior "
                         "P(class | height, normal) is divided by P(class)^this: 0 keeps it as learned, 1 is the ratio "
                         "that no longer favours a class for being common (docs/voxelcrf.md)"),
            OptionNumber(&O::layout_pseudo_count, "layout_pseudo_count", 0, 1e9, "voxels",
                         "layout prior divided by the class frequency: pseudo-voxels that shrink each height / normal cell's class "
                         "frequencies towards the overall ones"),
        },
        NestedOptions(&O::planes, PlaneDetectionOptions::Options()),
    });
    return table;
  }
  bool Check(std::string* error) const;
};

// The CRF of one visibility state V, in feature form: E(l) = w . Psi(l).
struct VoxelCrfProblem {
  int num_nodes = 0, num_labels = 0;  // L = K + 1.
  // Per node and label, the unary features: label 0 uses [kWDepthEmpty, kWDensityEmpty]; labels >= 1 use
  // appearance (per label), depth, density, unseen, bias, layout (per label).
  std::vector<float> f_depth_empty, f_density_empty, f_depth_occ, f_density_occ;
  std::vector<uint8_t> state;       // Per node: the map's VoxelState.
  std::vector<uint8_t> keep_occupied;  // Per node: 1 = the empty label is barred (kKeepOccupiedCost); empty: none.
  static constexpr float kKeepOccupiedCost = 1e4f;
  std::vector<float> f_appearance;  // N x K, 0 where not visible.
  std::vector<float> f_layout;      // N x K.
  std::vector<float> f_segment;     // N x K, -log P(class | segment shape); 0 outside segments; empty: none.
  struct Edge {
    int i, j;
    int16_t type;  // Weight index (kWPairwise3d + t or kWPairwise2d).
  };
  std::vector<Edge> edges;
  struct Clique {
    std::vector<int> nodes;
    float q = 1;
    int16_t type;  // kWPlane or kWObject.
  };
  std::vector<Clique> cliques;
  // The energy for weights w; with `loss_gt` (per node label), the loss-augmented energy E - Delta.
  CrfEnergy Energy(const std::array<double, kNumVoxelCrfWeights>& w, const std::vector<int>* loss_gt = nullptr) const;
  // Psi(l): E(l) = w . Psi(l).
  std::array<double, kNumVoxelCrfWeights> Features(const std::vector<int>& labels) const;
};

// Visibility (Eq. 9): per ray, the node of the first voxel along it whose label is occupied (or -1).
// With `starts` (ComputeRayStarts), each walk begins where its ray first meets a CRF node: the cells before
// that are outside the CRF, so their state never changes (same result, a fraction of the steps).
std::vector<int32_t> ComputeVisibility(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev,
                                       const std::vector<int>& labels, const std::vector<float>* starts = nullptr);

// Per ray, the distance along it from its origin at which its visibility walk may start: the middle of the
// last cell before the first CRF node it meets (0 when its origin cell is a node), or -1 when the ray meets
// an occupied voxel outside the CRF, or leaves the grid, before any node: its visible node is -1 whatever
// the labels.
std::vector<float> ComputeRayStarts(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev);

// Per node, a 64-bit fingerprint of every term of the problem that involves it: its unary features and map
// state, its edges (other end and type) and its cliques (members, truncation and type). Two problems over
// the same nodes give a node the same fingerprint when its terms are the same (up to hash collisions).
std::vector<uint64_t> NodeFingerprints(const VoxelCrfProblem& problem);

// The nodes whose fingerprints differ, and those within `rings` edges of them (over `problem`'s edges).
std::vector<uint8_t> ChangedNodes(const VoxelCrfProblem& problem, const std::vector<uint64_t>& before,
                                  const std::vector<uint64_t>& after, int rings);

// Builds the problem for the visibility `visible_node_of_ray`.
VoxelCrfProblem BuildVoxelCrfProblem(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev,
                                     double floor_z, double ceiling_z, const VoxelCrfModel& model,
                                     const std::vector<DetectedPlane>& planes, const VoxelCrfOptions& options,
                                     const std::vector<int32_t>& visible_node_of_ray);

struct VoxelCrfIteration {
  double energy_initial = 0, energy_final = 0;
  std::vector<double> energy_per_sweep;
  int sweeps = 0;
  int64_t changed_labels = 0;   // Against the previous iteration.
  int64_t movable_nodes = 0;    // Nodes the iteration's solve could relabel (all of them in the first).
  int64_t visible_nodes = 0;
  int64_t changed_visibility = 0;  // Rays whose visible node changed after this iteration.
  size_t edges = 0, cliques = 0;
  double seconds = 0;
  // Where the iteration's time went: problem construction (appearance, edges, cliques), energy tables,
  // alpha-expansion (of which max-flow), visibility walk.
  double seconds_build = 0, seconds_energy = 0, seconds_expansion = 0, seconds_max_flow = 0, seconds_visibility = 0;
};

struct VoxelCrfResult {
  std::vector<int> labels;            // Per node: 0 empty, k >= 1 class k - 1.
  std::vector<float> confidence;      // Per node: p(l_i | neighbours) under the final energy.
  std::vector<uint8_t> visible;       // Per node: visible in some classified-view ray (final V).
  std::vector<int32_t> visibility;    // Per ray: visible node.
  std::vector<VoxelCrfIteration> iterations;
  int num_planes = 0, num_object_cliques = 0;
  double seconds = 0;
  // Plane detection, ray starts with V_0, confidence (once each).
  double seconds_planes = 0, seconds_ray_starts = 0, seconds_confidence = 0;
};

Status SolveVoxelCrf(const VoxelGrid& grid, const VoxelCrfNodes& nodes, const VoxelEvidence& ev, double floor_z,
                     double ceiling_z, const VoxelCrfModel& model, const VoxelCrfOptions& options, VoxelCrfResult* result);

}  // namespace semvox
