// The semantic stage of `semvox run`: per-view classification of virtual views, evidence per
// voxel, the Voxel-CRF, and the semantic exports (voxels.ply, map.ot, semantic_topview*.png).
//
//   SemanticStage stage(scene, map, renderer, config);       // selects the CRF's voxels
//   RunViewsStage(..., stage.DepthSink(), ...);              // every kept view adds depth evidence
//   stage.ClassifyViews(positions);                          // classification views + room-type evidence
//   stage.Solve();                                           // Alg. 1
//   stage.Write(outdir, room_ids)                            // exports
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>
#include <nlohmann/json.hpp>
#include "core/geometry.h"
#include "core/option_table.h"
#include "core/status.h"
#include "mapping/voxelizer.h"
#include "render/view_renderer.h"
#include "render/view_selection.h"
#include "render/views.h"
#include "voxelcrf/semantic_map.h"
#include "voxelcrf/voxel_crf.h"
#include "voxelcrf/voxel_crf_learning.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {
struct ViewClassification;  // perception/view_classifier.h
}  // namespace semvox

namespace semvox {

// Which candidate classification views are classified.
enum class ClassifyViewSelection {
  kAll,    // Every candidate that passes the classifier's filters.
  kCover,  // The greedy multi-cover of the surface voxels (render/view_selection.h).
  kAllObjectsOnCover,  // Every candidate is classified (labels and room-type evidence), but only the cover's
                       // views go to the view hook (the support / clutter stage).
  kAuto,   // kCover for every input (resolved by `semvox run` once the input is loaded). Point clouds used to
           // classify every view for their room-type evidence; since the room-shape evidence and the cloud
           // Voxel-CRF weights (which give the per-view evidence almost no weight), the cover keeps the
           // randomised clouds' labels and room types within 0.2 points and the studio's box scores.
};
const char* ClassifyViewSelectionName(ClassifyViewSelection s);  // "all", "cover", "all_objects_on_cover", "auto"
bool ParseClassifyViewSelection(const std::string& name, ClassifyViewSelection* s);
// `s`, with kAuto resolved for `scene` (kCover for meshes and point clouds).
ClassifyViewSelection ResolveViewSelection(ClassifyViewSelection s, const Scene& scene);

// Which Voxel-CRF weights are used.
enum class VoxelCrfModelChoice {
  kMesh,   // models/voxel_crf.txt: trusts the per-view evidence, which is reliable only on what the per-view
           // classifiers learned from: meshes with one flat colour per surface (the generator's style).
  kCloud,  // models/voxel_crf_cloud.txt: learned on simulated fused clouds (`--voxel-crf-style cloud`); the
           // per-view evidence gets almost no weight, the object segments count most. Falls back to
           // voxel_crf.txt with a warning when absent.
  kAuto,   // kMesh for flat-coloured meshes (FlatColouredMesh), kCloud for point clouds and every other mesh
           // (textured, colour per vertex as scanned, or no colour); resolved by `semvox run`.
};
const char* VoxelCrfModelChoiceName(VoxelCrfModelChoice c);  // "mesh", "cloud", "auto"
bool ParseVoxelCrfModelChoice(const std::string& name, VoxelCrfModelChoice* c);

// A mesh coloured like the generator's: vertex colours, no texture, and at least half the faces with one
// colour on all three vertices. A scanned mesh's colours vary from vertex to vertex; a textured or
// uncoloured mesh gives the per-view classifiers no flat colours either.
bool FlatColouredMesh(const Mesh& mesh);

struct SemanticStageOptions {
  bool enabled = true;
  double classify_yaw_step_deg = 30.0;
  // The shipped classifiers were trained on 320 x 240 views (the SLIC superpixel size and the dense CRF's
  // kernel widths are in pixels), so other sizes trade labels for speed.
  int classify_width = 320;
  int classify_height = 240;
  ClassifyViewSelection view_selection = ClassifyViewSelection::kAuto;
  VoxelCrfModelChoice crf_model = VoxelCrfModelChoice::kAuto;
  ViewSelectionOptions selection;  // For kCover.
  VoxelEvidenceOptions evidence;
  VoxelCrfOptions crf;

  // The fields users set (section `semantic`, with those of selection, evidence and crf): meaning, unit and range.
  static const OptionTable<SemanticStageOptions>& Options() {
    using O = SemanticStageOptions;
    static const OptionTable<O> table = JoinOptions<O>({
        {
            OptionSwitch(&O::enabled, "enabled",
                         "run the per-view classifiers and the Voxel-CRF (voxels.ply, map.ot, semantic top view)"),
            OptionNumber(&O::classify_yaw_step_deg, "classify_yaw_step_deg", 1, 360, "degrees",
                         "yaw between candidate classification views of a viewpoint (divides 360)"),
            OptionChoice(&O::view_selection, "view_selection", {"auto", "cover", "all", "all_objects_on_cover"},
                         ParseClassifyViewSelection,
                         "classification views: cover (the fewest candidates that see each surface voxel "
                         "min_views_per_voxel times, greedy set cover), all, all_objects_on_cover (every view "
                         "classified, the support / clutter stage on the cover's views only), or auto (cover)"),
            OptionChoice(&O::crf_model, "voxel_crf_model", {"auto", "mesh", "cloud"}, ParseVoxelCrfModelChoice,
                         "Voxel-CRF weights: mesh (models/voxel_crf.txt, trusts the per-view classifiers), cloud "
                         "(models/voxel_crf_cloud.txt, learned on simulated fused clouds: the object segments count "
                         "most), or auto (mesh for meshes with one flat colour per surface, as the generator makes "
                         "them; cloud for point clouds and scanned, textured or uncoloured meshes)"),
        },
        NestedOptions(&O::selection, ViewSelectionOptions::Options()),
        {
            OptionNumber(&O::classify_width, "classify_width", 16, 4096, "pixels",
                         "classification view width (the shipped classifiers are trained at 320)"),
            OptionNumber(&O::classify_height, "classify_height", 16, 4096, "pixels",
                         "classification view height (trained at 240)"),
        },
        NestedOptions(&O::evidence, VoxelEvidenceOptions::Options()),
        NestedOptions(&O::crf, VoxelCrfOptions::Options()),
    });
    return table;
  }
  bool Check(std::string* error) const;
};

// Room-type evidence of one classification view (for the room-type CRF).
struct ClassifiedViewRoomEvidence {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw_rad = 0, hfov_rad = 0, max_range_m = 0;
  std::array<double, 12> p{};  // room_types.tsv ids 1..12 (index id - 1).
};

class SemanticStage {
 public:
  // Loads the classifier and the CRF model from `models_dir` (second.*, room_type_knn.bin, object_segments.knn,
  // voxel_crf.txt or voxel_crf_cloud.txt by options.crf_model).
  static Result<std::unique_ptr<SemanticStage>> Create(const VoxelMap& map, const ViewRenderer& renderer,
                                                       const SemanticStageOptions& options, const std::string& models_dir);
  ~SemanticStage();
  // Optional: the user's ONNX networks replace the built-in per-view classifier and room-type evidence.
  void SetOnnxModels(const struct OnnxModels* models);
  // Optional: the work to do on each used classification view (e.g. the support / clutter stage); with
  // kAllObjectsOnCover only on the cover's views. The hook runs on several views at once, next to their
  // classification, so it must be safe to call concurrently; what it returns runs once per view, in view
  // order, on one thread (fusion), so the results do not depend on the threads. `classified` is the view's
  // per-view classification (its superpixels and observations, for other classifiers of the same
  // segmentation), or null when the ONNX networks replaced the built-in classifier.
  using ViewHook = std::function<Result<std::function<Status()>>(const RenderedView&, const ViewClassification* classified)>;
  void SetViewHook(ViewHook hook);
  // Adds the depth, density, colour and normal evidence of every kept view.
  ViewSink DepthSink();
  // Renders and classifies the classification views from `positions` (x, y; the camera stands at the
  // classifier's training eye height above the floor, looking down as in training).
  Status ClassifyViews(const std::vector<Eigen::Vector3d>& positions);
  Status Solve();
  // Solves again with other CRF options (variants U, U+PW, U+PW+G; iterations) over the same evidence.
  Status SolveWith(const VoxelCrfOptions& crf);
  const VoxelCrfResult& crf_result() const;
  // The refined occupancy grid (after Solve).
  const VoxelGrid& refined_grid() const;
  const SemanticMap& semantic_map() const;
  SemanticMap* mutable_semantic_map();
  const std::vector<ClassifiedViewRoomEvidence>& room_evidence() const;
  // voxels.ply, map.ot, semantic_topview.png, semantic_topview_labels.png (rooms assigned from room_ids).
  // voxels.ply's coordinates are mapped by `input_from_world` (canonical frame back to the input frame);
  // map.ot and the top views stay on the grid (canonical frame).
  Status Write(const std::string& outdir, const ImageU16* room_ids, double band_min_m, double band_max_m,
               const ImageRgb8& occupancy_image, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());
  nlohmann::ordered_json Summary() const;

  // ---- For `semvox train --voxel-crf` ----
  // Finishes the evidence (Solve does it too).
  void FinishEvidence();
  // Per node the ground-truth label (0 empty, k >= 1 class k - 1) from NYU40 labels per packed voxel key.
  std::vector<int> GroundTruthNodeLabels(const std::unordered_map<uint64_t, int>& nyu40_of_key) const;
  // Adds the layout-prior counts (LayoutPrior layout, K classes) of the ground-truth occupied nodes.
  void AddLayoutCounts(const std::vector<int>& gt, std::vector<double>* counts) const;
  // The CRF problem under the ground truth's visibility, for structural-SVM learning.
  VoxelCrfTrainingExample TrainingExample(std::vector<int> gt, const VoxelCrfModel& model) const;
  const VoxelCrfNodes& nodes() const;
  const VoxelCrfModel& model() const;

 private:
  struct Impl;
  explicit SemanticStage(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The NYU40 id written for each class of `level` ("other" -> otherprop), before training picks better.
std::vector<int> Nyu40OfClasses(const struct LabelLevel& level);

}  // namespace semvox
