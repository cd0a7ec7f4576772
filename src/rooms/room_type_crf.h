// Room-type CRF (the room-labelling paper, Sec. V-VI): a room type for every floor cell and every room.
//
//   FloorPlan + RoomSegmentation + per-view room-type distributions (ViewRoomEvidence) + semantic top view
//     --InferRoomTypes--> RoomTypeResult (per-pixel type and marginals, per-room type / probability / second
//                                         type, rooms split where the cells support it)
//
// Nodes are small cells of the floor plan (cell_size_m squares, each square split by room id so a node never
// straddles a wall), over the room extent (free, door and clutter pixels with a room). The energy (Eq. 1),
// maximised, with p(y) proportional to exp(E(y)):
//   E(y) = sum_i w_c phi_scene(y_i, s_i) + sum_i w_obj^T phi_obj(y_i, o_i) + w_hom sum_{i<j} f(y_i, g_i, y_j, g_j, d_ij)
//  - phi_scene: s_i is the mean of the distributions of the views whose cone (clipped by walls: 2D ray casting
//    on the plan, up to max_range_m) covers the cell; uniform where no view does. phi_cnn = s_y (Eq. 2);
//    phi_conf = sum_l p_trn(y, l) s_l (Eq. 3), p_trn(y, l) = P(true type y | view argmax l) over the training
//    pixels.
//  - phi_obj (Eq. 4-5): o_i[k] = exp(-d_k^2 / 2 sigma^2) with d_k the distance from the cell to the nearest
//    top-view cell of NYU40 object k in the same room (0 when none); phi_obj^g(y) = sum_{k in group g}
//    o_i[k] p_stat[k][y], p_stat[k][y] = P(y | k) with a uniform type prior from the object-to-room counts
//    (RoomTypeModel). Groups (kObjectGroups): 1 large furniture, 2 small objects of daily use, 3 kitchen and
//    bathroom fixtures, 4 bed and sofa.
//  - phi_hom (Eq. 6-7) over pairs within max_pair_distance_m: the four events (same/different type x
//    same/different segment). phi_stat: f = log P(type relation | segment relation, distance bin), learned
//    from the training apartments' ground truth; phi_gauss: fixed costs per event times exp(-d^2 / 2 sigma^2).
//    The pair sum is divided by the expected number of neighbours, so w_hom is on the unaries' scale.
// Inference (Sec. V-C): Gibbs sampling, initialised by drawing each node from its scene distribution, nodes
// visited in a fresh random order every sweep (seed in the options); marginals are the sample frequencies after
// burn-in. Weights (w_c, w_obj, w_hom) by a structural SVM (stochastic subgradient, loss = per-node
// disagreement weighted by pixels; loss-augmented inference by iterated conditional modes).
// Baselines (Sec. VI): majority voting per segment, and a dense Gaussian CRF with mean-field inference.
// Rooms: type = argmax of the room's aggregated (pixel-summed) marginals, with its probability, and the
// second type with its. Split rule: a 4-connected area of pixels whose argmax type differs from the room's,
// of at least min_split_area_m2 and min_split_fraction of the room, whose mean marginal of that type is at
// least min_split_probability, becomes a room of its own (new id after the existing ones).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/option_table.h"
#include "core/status.h"
#include "rooms/floor_plan.h"
#include "rooms/room_segmentation.h"
#include "rooms/room_shape.h"

namespace semvox {

inline constexpr int kRoomTypeLabels = 12;  // room_types.tsv ids 1..12; index = id - 1.
inline constexpr int kNumObjectGroups = 4;

// One classified view: where it was taken and what it says about the room type.
struct ViewRoomEvidence {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // Camera centre, world frame (z ignored), metres.
  double yaw_rad = 0;          // Heading of the optical axis in the x-y plane, from +x towards +y.
  double hfov_rad = 1.047;     // Horizontal field of view, radians.
  double max_range_m = 6.0;    // The cone ends here, metres.
  std::array<double, kRoomTypeLabels> p{};  // Per-view room-type distribution (index = id - 1).
};

// Object group (0..3) of an NYU40 id, or -1 for ids that are no room cue (structure, floor, ...).
int ObjectGroupOf(int nyu40);

enum class ScenePotential { kCnn, kConfusion };          // Eq. 2, Eq. 3.
enum class HomogeneityPotential { kNone, kStatistics, kGaussian };  // -, phi_stat, phi_gauss.
const char* ScenePotentialName(ScenePotential s);        // "cnn", "conf".
const char* HomogeneityPotentialName(HomogeneityPotential h);  // "none", "stat", "gauss".
bool ParseScenePotential(const std::string& name, ScenePotential* out);
bool ParseHomogeneityPotential(const std::string& name, HomogeneityPotential* out);

// Which terms of Eq. 1 a model uses; names a weight vector in the model file ("conf+gauss+obj").
struct RoomTypeVariant {
  ScenePotential scene = ScenePotential::kConfusion;
  HomogeneityPotential homogeneity = HomogeneityPotential::kGaussian;
  bool objects = true;
  std::string Name() const;

  // The terms users choose (section `room_types`).
  static const OptionTable<RoomTypeVariant>& Options() {
    using O = RoomTypeVariant;
    static const OptionTable<O> table = {
        OptionChoice(&O::scene, "scene", {"cnn", "conf"}, ParseScenePotential,
                     "scene potential: cnn (Eq. 2, s_y) or conf (Eq. 3, with the training confusion)"),
        OptionChoice(&O::homogeneity, "homogeneity", {"none", "stat", "gauss"}, ParseHomogeneityPotential,
                     "homogeneity potential (Eq. 6-7): none, stat (learned distance statistics) or gauss (fixed costs x Gaussian)"),
        OptionNumber(&O::objects, "objects", 0, 1, "", "object-occurrence potential (Eq. 4-5): 1 on, 0 off"),
    };
    return table;
  }
};

// Weights of Eq. 1: w_c, w_obj (4), w_hom.
struct RoomTypeWeights {
  double scene = 1;
  std::array<double, kNumObjectGroups> objects{1, 1, 1, 1};
  double homogeneity = 1;
};

// Dense Gaussian CRF baseline parameters (Eq. 9; the segment id plays the role of the colour feature).
struct DenseCrfParams {
  double w_appearance = 3;      // w(1): kernel over position within the same segment.
  double theta_alpha_m = 1.5;   // Its position scale, metres.
  double w_smooth = 1;          // w(2): position-only kernel.
  double theta_gamma_m = 0.5;   // Its scale, metres.
};

// Everything `semvox train` learns (models/room_type_crf.json).
struct RoomTypeModel {
  // p_trn(y, l) = P(true type y | view argmax l), Eq. 3: confusion[l][y].
  std::array<std::array<double, kRoomTypeLabels>, kRoomTypeLabels> confusion{};
  // P(y | object k present) with a uniform type prior, Eq. 5: object_type[k][y], k = NYU40 id.
  std::vector<std::array<double, kRoomTypeLabels>> object_type;
  // phi_stat (Eq. 6): log P(same type | same segment, distance bin) etc.; bins of hom_bin_m.
  double hom_bin_m = 0.25;
  std::vector<std::array<double, 4>> hom_log_prob;  // Per bin: [same y & same g, diff y & same g, same y & diff g, diff y & diff g].
  std::vector<std::pair<std::string, RoomTypeWeights>> weights;  // Per variant name.
  // log P(no fixture | y): a room of type y holds none of the fixtures of real plans (counter, toilet, sink,
  // bathtub; R2vFixtureLabels), from the rooms of the R2V training plans and the generated apartments (Laplace
  // smoothing). All zero (the term off) in models written before it existed.
  std::array<double, kRoomTypeLabels> no_fixture_log_prob{};
  DenseCrfParams dense;
  std::string provenance;  // What it was trained on (free text, for the report).

  // Weights of `variant`; all 1 when the model has none for it.
  RoomTypeWeights WeightsFor(const RoomTypeVariant& variant) const;
  void SetWeights(const RoomTypeVariant& variant, const RoomTypeWeights& w);
  // Uninformative statistics: identity confusion, uniform object statistics, flat homogeneity statistics.
  static RoomTypeModel Uninformative();
};

std::string RoomTypeModelToJson(const RoomTypeModel& model);
Status SaveRoomTypeModel(const RoomTypeModel& model, const std::string& path);
Result<RoomTypeModel> LoadRoomTypeModel(const std::string& path);

struct RoomTypeCrfOptions {
  RoomTypeVariant variant;              // Terms of Eq. 1 (default: conf + gauss + obj, the paper's best).
  std::string model_path;               // Model file (the caller's: `semvox run` gives <models>/room_type_crf.json).
  std::string shape_model_path;         // Room-shape model (<models>/room_shape.json); empty = rooms typed without their shapes.
  double cell_size_m = 0.25;
  double max_pair_distance_m = 3.0;
  double gauss_sigma_m = 1.0;
  double gauss_same_segment = 1.0;      // The cost of different types in one segment is its negative.
  double gauss_other_segment = 0.1;
  double object_sigma_m = 1.5;          // Eq. 5 o_i.
  // The semantic top view the object term reads passes over voxels whose label confidence is lower (`semvox
  // run`'s rooms stage; a label the Voxel-CRF barely prefers is as likely a wall misread as an object). 0.5
  // goes with semantic.layout_frequency_power 1 (docs/voxelcrf.md); at power 0 it costs the plans 1.5 points.
  double min_object_confidence = 0;
  // A piece of furniture in the top view is an 8-connected group of object cells (any class of the four object
  // groups) in one room. A class's object evidence in a room is scaled by its largest share of a piece over
  // min_object_share, capped at 1: a patch of sofa or television read on a bed counts little, a sofa of its own
  // (or a kitchen counter in an open-plan room) fully. 0 = every class present counts fully (the paper's Eq. 5).
  // 0.3 since 2026-12-04, chosen through `semvox run` on R2V training plans 250-269 and generated apartments
  // 40-44 (docs/rooms.md); on a clean ground-truth top view it costs (true objects standing on others).
  double min_object_share = 0.3;
  int burn_in_sweeps = 20;
  int sample_sweeps = 100;
  uint64_t seed = 1;                    // Gibbs sampling order and draws.
  double min_split_area_m2 = 4.0;
  double min_split_fraction = 0.1;    // A studio's kitchenette is an eighth of its room (0.2 until 2026-12-06, 0.25 before).
  double min_split_probability = 0.5;
  // Room shapes (room_shape.h): every node's unary gains shape_weight x its room's log-likelihood ratios
  // under the room-shape model (phi_shape, next to the scene and object terms). 3 since 2026-12-04 (was 0.5),
  // chosen on R2V training plans 250-269 and generated apartments 40-44 through `semvox run` (docs/rooms.md).
  double shape_weight = 3.0;
  // Room adjacency (room_shape.h, RoomShapeModel::adjacency, learnt with the shapes): every node's unary gains
  // adjacency_weight x sum over its room's neighbours of the expected log ratio of the two types under the
  // neighbour's current label shares (refreshed every sweep). Needs the room-shape model. Off by default: through
  // `semvox run` it lowered the room types of the plans and apartments it was chosen on (docs/rooms.md).
  double adjacency_weight = 0.0;
  // Fixtures seen nowhere in a room: every node of a room whose semantic top view holds no cell of a fixture
  // class (counter, toilet, sink, bathtub) gains fixture_absence_weight x log P(no fixture | y)
  // (RoomTypeModel::no_fixture_log_prob). A closet and a WC have the same size and shape; only the toilet tells
  // them apart, and its absence says as much as its presence. Off without a semantic top view. 1.5 since
  // 2026-12-05, chosen through `semvox run` on R2V training plans 200-249 and generated apartments 40-44 by the
  // mean of their pixel accuracies (docs/rooms.md, "Fixtures seen nowhere").
  double fixture_absence_weight = 1.5;

  // The fields users set (section `room_types`): meaning, unit and range.
  static const OptionTable<RoomTypeCrfOptions>& Options() {
    using O = RoomTypeCrfOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        NestedOptions(&O::variant, RoomTypeVariant::Options()),
        {
            OptionNumber(&O::cell_size_m, "cell_size_m", 0.05, 5, "metres", "CRF node size"),
            OptionNumber(&O::max_pair_distance_m, "max_pair_distance_m", 0.1, 50, "metres",
                         "homogeneity pairs up to this far apart"),
            OptionNumber(&O::gauss_sigma_m, "gauss_sigma_m", 0.01, 50, "metres", "phi_gauss kernel width"),
            OptionNumber(&O::gauss_same_segment, "gauss_same_segment", 0, 100, "",
                         "phi_gauss: reward for equal types in one segment"),
            OptionNumber(&O::gauss_other_segment, "gauss_other_segment", 0, 100, "", "phi_gauss: ... in different segments"),
            OptionNumber(&O::object_sigma_m, "object_sigma_m", 0.01, 50, "metres", "reach of an object's evidence"),
            OptionNumber(&O::min_object_confidence, "min_object_confidence", 0, 1, "",
                         "the object term reads the semantic top view without the voxels whose label confidence "
                         "is lower"),
            OptionNumber(&O::min_object_share, "min_object_share", 0, 1, "",
                         "an object class counts fully in a room only where it makes at least this share of a piece of "
                         "furniture in the top view (8-connected object cells), proportionally less below; 0 = always fully"),
            OptionNumber(&O::burn_in_sweeps, "burn_in_sweeps", 0, 100000, "", "Gibbs sweeps discarded"),
            OptionNumber(&O::sample_sweeps, "sample_sweeps", 1, 1000000, "", "Gibbs sweeps counted into the marginals"),
            OptionNumber(&O::seed, "seed", 0, 4294967295.0, "", "seed of the Gibbs sampler"),
            OptionNumber(&O::min_split_area_m2, "min_split_area_m2", 0, 10000, "m2",
                         "a room is split only off areas this large"),
            OptionNumber(&O::min_split_fraction, "min_split_fraction", 0, 1, "", "... covering this fraction of the room"),
            OptionNumber(&O::min_split_probability, "min_split_probability", 0, 1, "",
                         "... whose mean marginal of their type is at least this"),
            OptionNumber(&O::shape_weight, "shape_weight", 0, 10, "",
                         "weight of the room-shape evidence learnt from real plans (models/room_shape.json), 0 = off"),
            OptionNumber(&O::adjacency_weight, "adjacency_weight", 0, 10, "",
                         "weight of the room-adjacency term learnt from real plans (which types neighbour which), 0 = off"),
            OptionNumber(&O::fixture_absence_weight, "fixture_absence_weight", 0, 10, "",
                         "weight of log P(no fixture | type) in rooms whose semantic top view shows no counter, toilet, "
                         "sink or bathtub (learnt from real plans), 0 = off"),
        },
    });
    return table;
  }
  bool Check(std::string* error) const;
};

// The CRF's inputs on the plan, computed once and shared by the methods (exposed for tests and training).
struct RoomTypeGraph {
  int width = 0, height = 0;
  std::vector<int> node_of_pixel;     // Per pixel, -1 outside the room extent.
  std::vector<Eigen::Vector2d> position;  // Node centroids, metres.
  std::vector<int> segment;           // Room id per node.
  std::vector<int> pixels;            // Pixel count per node.
  std::vector<std::array<double, kRoomTypeLabels>> scene;  // s_i (mean projected distribution).
  std::vector<bool> covered;          // Some view's cone covers the node.
  std::vector<std::array<double, kRoomTypeLabels>> best_view;  // Distribution of the covering view with the
                                                               // highest maximum (dense CRF baseline).
  std::vector<std::array<double, kRoomTypeLabels>> votes;      // Per type: pixels x views voting (majority).
  std::vector<std::array<std::array<double, kRoomTypeLabels>, kNumObjectGroups>> objects;  // phi_obj^g(y).
  // Per node: its room's semantic top view holds no fixture cell (RoomTypeCrfOptions::fixture_absence_weight);
  // empty without a top view.
  std::vector<bool> without_fixture;
  // Neighbours within max_pair_distance_m (both directions), with the distance.
  std::vector<std::vector<std::pair<int, float>>> neighbours;
  double pair_normaliser = 1;         // Expected neighbour count (the pair sum is divided by it).
  // phi_shape per node: its room's log-likelihood ratios (room_shape.h); empty when no shape model is used.
  std::vector<std::array<double, kRoomTypeLabels>> shape;
  // The adjacency term: per room id (index = id, 0 unused) its neighbouring room ids, and the model's log
  // ratios (room_shape.h); room_neighbours is empty when the term is not used.
  std::vector<std::vector<int>> room_neighbours;
  std::array<std::array<double, kRoomShapeTypes>, kRoomShapeTypes> adjacency{};
};

// Per pixel: how many of the views' cones cover it (2D ray casting on the plan; walls and unknown cells stop
// a ray; door, free and clutter cells let it pass).
Image<uint16_t> ProjectViewCones(const FloorPlan& plan, const std::vector<ViewRoomEvidence>& views);

Result<RoomTypeGraph> BuildRoomTypeGraph(const FloorPlan& plan, const RoomSegmentation& rooms,
                                         const std::vector<ViewRoomEvidence>& views,
                                         const Image<uint16_t>& topview_labels, const RoomTypeModel& model,
                                         const RoomTypeCrfOptions& options);

// Unary potential of node i, label y (weighted sum of scene and object terms), and the pair potential.
struct RoomTypeEnergy {
  const RoomTypeGraph* graph = nullptr;
  const RoomTypeModel* model = nullptr;
  RoomTypeVariant variant;
  RoomTypeWeights weights;
  RoomTypeCrfOptions options;
  // Feature vector entries: [scene, obj1..4, hom]; the shape term (options.shape_weight) is fixed, not learnt.
  double Scene(int i, int y) const;
  double Object(int i, int g, int y) const;
  // The unary's weighted parts (Unary is their sum, in this order; the per-room terms of RoomTypeAssignment).
  double SceneTerm(int i, int y) const;
  double ObjectTerm(int i, int g, int y) const;
  double ShapeTerm(int i, int y) const;  // 0 without a shape model.
  double FixtureTerm(int i, int y) const;  // 0 in rooms with a fixture, or without a top view.
  double Unary(int i, int y) const;
  // f(y_i, g_i, y_j, g_j, d) of the variant for a pair (same type?, same segment?, distance), unweighted.
  double Pair(bool same_type, bool same_segment, double distance_m) const;
  double Total(const std::vector<int>& labels) const;
};

struct GibbsSummary {
  int sweeps = 0;
  double seconds = 0;
};

// Per-node marginals from Gibbs sampling (Sec. V-C).
std::vector<std::array<double, kRoomTypeLabels>> GibbsMarginals(const RoomTypeEnergy& energy, const RoomTypeCrfOptions& options,
                                                               GibbsSummary* summary = nullptr);
// Exact marginals by enumeration (tests; at most 8 nodes).
std::vector<std::array<double, kRoomTypeLabels>> ExactMarginals(const RoomTypeEnergy& energy, int num_labels_used = kRoomTypeLabels);

// Baselines, per node label distributions (one-hot for majority voting).
std::vector<std::array<double, kRoomTypeLabels>> MajorityVoting(const RoomTypeGraph& graph);
std::vector<std::array<double, kRoomTypeLabels>> DenseGaussianCrf(const RoomTypeGraph& graph, const DenseCrfParams& params,
                                                                 int iterations = 10);

struct RoomTypeAssignment {
  int id = 0;              // Room id (after splitting).
  int source_room = 0;     // Id in the input segmentation.
  int type_id = 0;         // room_types.tsv id (1..12).
  double probability = 0;
  int second_type_id = 0;
  double second_probability = 0;
  std::array<double, kRoomTypeLabels> probabilities{};
  // The Gibbs CRF's unary terms, pixel-weighted means over the room's nodes, as weighted in the energy: the
  // scene (views), the object groups (summed) and the room shape. Which evidence decided a room (zero when
  // the term is off or another method ran), and the absence of fixtures.
  std::array<double, kRoomTypeLabels> scene_term{}, object_term{}, shape_term{}, fixture_term{};
};

struct RoomTypeResult {
  ImageU16 pixel_types;          // Type id (1..12) per room-extent pixel, argmax of its node's marginal; 0 elsewhere.
  RoomSegmentation rooms;        // The input rooms, with split-off areas as new ids.
  std::vector<RoomTypeAssignment> assignments;  // One per room of `rooms`.
  std::vector<std::array<double, kRoomTypeLabels>> node_marginals;
  int splits = 0;
  double seconds = 0;
  std::vector<RoomShape> shapes;  // Per input room (index = id - 1) when the shape term ran.
};

enum class RoomTypeMethod { kGibbsCrf, kMajorityVoting, kDenseCrf };

// Room types from node marginals: per-pixel argmax, per-room aggregation and the split rule.
RoomTypeResult AssignRoomTypes(const RoomTypeGraph& graph, const RoomSegmentation& rooms, const FloorPlan& plan,
                               std::vector<std::array<double, kRoomTypeLabels>> marginals, const RoomTypeCrfOptions& options);

// Sets graph->shape from the shapes of rooms 1..rooms.num_rooms (room_extent_ids; rooms that touch there are
// connected) and, when the model has learnt its adjacency, graph->room_neighbours and graph->adjacency;
// returns those shapes.
std::vector<RoomShape> SetRoomShapeEvidence(const RoomSegmentation& rooms, const FloorPlan& plan, const RoomShapeModel& shapes,
                                            RoomTypeGraph* graph);

// The whole stage: graph, inference with `method`, the room shapes when `shapes` is given, room assignment.
Result<RoomTypeResult> InferRoomTypes(const FloorPlan& plan, const RoomSegmentation& rooms,
                                      const std::vector<ViewRoomEvidence>& views, const Image<uint16_t>& topview_labels,
                                      const RoomTypeModel& model, const RoomTypeCrfOptions& options,
                                      RoomTypeMethod method = RoomTypeMethod::kGibbsCrf, const RoomShapeModel* shapes = nullptr);

// Training -----------------------------------------------------------------------------------------------

// One labelled apartment for training: its plan, segmentation, views, top view and true type per pixel.
struct RoomTypeTrainingScene {
  FloorPlan plan;
  RoomSegmentation rooms;
  std::vector<ViewRoomEvidence> views;
  ImageU16 topview;
  ImageU16 truth;  // True type id per pixel (0 = not scored).
};

// Object-to-room-type counts: rooms of each type, and of those how many hold object k (NYU40).
struct ObjectRoomCounts {
  std::array<double, kRoomTypeLabels> rooms{};
  std::vector<std::array<double, kRoomTypeLabels>> with_object = std::vector<std::array<double, kRoomTypeLabels>>(41);
  std::array<double, kRoomTypeLabels> without_fixture{};  // Rooms holding none of R2vFixtureLabels().
  void Add(const ObjectRoomCounts& other);
};

// The NYU40 ids the R2V fixtures stand for (counter, toilet, sink, bathtub).
const std::vector<int>& R2vFixtureLabels();

// log P(no fixture | y) = log((rooms without a fixture + 1) / (rooms + 2)) per type.
std::array<double, kRoomTypeLabels> NoFixtureLogProb(const ObjectRoomCounts& counts);

// P(y | k) with a uniform type prior from counts (Laplace smoothing): objects absent from every room give a
// uniform row.
std::vector<std::array<double, kRoomTypeLabels>> ObjectTypeStatistics(const ObjectRoomCounts& counts);

// Node types from a truth image (majority over the node's pixels; -1 where none is scored).
std::vector<int> NodeTruth(const RoomTypeGraph& graph, const ImageU16& truth);

// Confusion (Eq. 3) from the scenes' projected views and truths.
void LearnConfusion(const std::vector<RoomTypeTrainingScene>& scenes, RoomTypeModel* model);
// phi_stat tables from the truth and segmentation of the scenes.
void LearnHomogeneityStatistics(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeCrfOptions& options,
                                RoomTypeModel* model);

struct SsvmOptions {
  int epochs = 30;            // Passes over the scenes. >= 1.
  double learning_rate = 2.0; // Step size at epoch 1 (decays as 1/sqrt(t)).
  double regularisation = 1e-3;  // lambda of 0.5 lambda |w|^2.
  uint64_t seed = 7;
};
// Structural SVM weights (stochastic subgradient) for `variant`; the graphs are built with `options`.
RoomTypeWeights LearnWeightsSsvm(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                 const RoomTypeVariant& variant, const RoomTypeCrfOptions& options, const SsvmOptions& ssvm);
// Scale of the weights for sampling. The SSVM fixes the direction of w (and, when the scene evidence is weak,
// drives a lone scene weight towards 0, which would make the sampler draw uniformly); the marginals' argmax
// depends on the scale (the sampler's temperature). Normalises w so that its largest entry is 1, picks the
// factor of `scales` whose Gibbs marginals (with the sweeps of `options`) give the best pixel accuracy on the
// scenes, and returns the scaled weights.
// With `shapes` (and options.shape_weight > 0) the scenes' rooms get the room-shape term at its fixed weight, as
// at run time, so the scale is chosen for the energy `semvox run` samples.
RoomTypeWeights CalibrateWeightScale(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                     const RoomTypeVariant& variant, const RoomTypeWeights& weights,
                                     const RoomTypeCrfOptions& options, const std::vector<double>& scales,
                                     double* chosen_scale = nullptr, const RoomShapeModel* shapes = nullptr);
// Dense CRF parameters by grid search (the paper, Sec. VI-B) maximising per-pixel accuracy.
DenseCrfParams LearnDenseCrfParams(const std::vector<RoomTypeTrainingScene>& scenes, const RoomTypeModel& model,
                                   const RoomTypeCrfOptions& options);

// Scoring: per-pixel accuracy of predicted type ids against truth (0 = not scored), accumulated per type.
struct RoomTypeAccuracy {
  std::array<double, kRoomTypeLabels + 1> correct{}, total{};
  void Add(const ImageU16& predicted, const ImageU16& truth);
  double Global() const;
  double Average() const;  // Mean recall over the types present in the truth.
};

// The type-coloured top view (rooms_types.png): room types in their colours, walls dark, clutter shaded.
ImageRgb8 RenderRoomTypes(const FloorPlan& plan, const ImageU16& pixel_types);

}  // namespace semvox
