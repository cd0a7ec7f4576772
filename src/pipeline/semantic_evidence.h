// Evidence building, the first part of the semantic stage: the models it reads, per-voxel evidence from the
// rendered views (depth, density, colour, normals), the classification views (per-view class probabilities and
// room-type evidence) and the object segments classified by shape.
//
//   Result<SemanticModels> models = SemanticModels::Load(models_dir, VoxelCrfModelChoice::kMesh);
//   Result<std::unique_ptr<SemanticEvidenceBuilder>> b = SemanticEvidenceBuilder::Create(map, renderer, options, *models);
//   RenderViews(renderer, map, views_options, (*b)->DepthSink());   // every kept view adds depth evidence
//   (*b)->ClassifyViews(positions);                                // classification views + room-type evidence
//   SemanticEvidence evidence = std::move(**b).Finish();           // + object segments
//
// What follows: SolveSemantic (pipeline/semantic_solve.h), the exports (pipeline/semantic_exports.h), and for
// `semvox train --voxel-crf` the training examples (pipeline/voxel_crf_examples.h).
#pragma once
#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/status.h"
#include "mapping/voxelizer.h"
#include "perception/label_levels.h"
#include "pipeline/semantic_options.h"
#include "render/view_renderer.h"
#include "render/view_selection.h"
#include "render/views.h"
#include "rooms/room_type_crf.h"
#include "voxelcrf/voxel_crf.h"
#include "voxelcrf/voxel_evidence.h"

namespace semvox {

struct ViewClassification;  // perception/view_classifier.h
class ViewClassifier;       // perception/view_classifier.h
class KnnClassifier;        // perception/knn_unary.h
class SegmentClassifier;    // objects/segment_classifier.h
class OtherLabeller;        // objects/other_labels.h
class ItemLabeller;         // objects/other_labels.h
struct SegmentationResult;  // objects/object_segments.h
struct OnnxModels;          // pipeline/onnx_stage.h

// The model files of the semantic stage.
struct SemanticModels {
  LabelLevel level;                                    // The per-view classifier's classes (SecondLevel()).
  std::shared_ptr<const ViewClassifier> classifier;   // second.*
  std::shared_ptr<const KnnClassifier> room_knn;      // room_type_knn.bin
  // Its training views' 0.99-quantile neighbour distance (KnnClassifier::TrainingNeighbourDistanceQuantile).
  double room_familiar_distance = 0;
  std::shared_ptr<const SegmentClassifier> segments;   // object_segments.forest or .knn; null when absent (no segment term).
  std::shared_ptr<const OtherLabeller> other;          // other_labels.knn; null when absent ("other" keeps one id).
  std::shared_ptr<const ItemLabeller> items;           // item_labels.knn; null when absent (items on top stay furniture).
  VoxelCrfModel crf;                                   // voxel_crf.txt or voxel_crf_cloud.txt, else untrained defaults.
  std::string crf_file;                                // File name of the loaded CRF model; "" for the defaults.

  // Loads them from `models_dir` (the CLI resolves it, apps/models_dir.h). A missing object-segment or CRF
  // model is a warning; a missing classifier or room-type k-NN, or models of different class counts, an error.
  static Result<SemanticModels> Load(const std::string& models_dir, VoxelCrfModelChoice crf_model);
};

// What the evidence building gives the solver, the room types and the summary.
struct SemanticEvidence {
  VoxelCrfNodes nodes;                                 // The CRF's voxels.
  VoxelEvidence voxels;                                // Their evidence (with the object segments' term).
  std::vector<ViewRoomEvidence> rooms;                 // Room-type evidence per used classification view.
  ViewSelection selection;                             // Candidates and cover (kCover), or candidates only.
  int classification_views = 0, skipped_views = 0;
  int hooked_views = 0;                                // Classified views the view hook saw.
  int num_segments = -1;                               // Object segments classified; -1 without a segment model.
  // The object segments (with either model), for the fine labels of "other" after the CRF; null without.
  std::shared_ptr<const SegmentationResult> segmentation;
  // Their voxels, and those of the segments shaped unlike every training segment (SegmentClassifier::
  // Unfamiliarity above 1; the k-NN only, else -1), and that many segments.
  int64_t segment_voxels = 0, unfamiliar_segment_voxels = -1;
  int unfamiliar_segments = -1;
  // Segments whose counter probability went to table because their top surface lies below counter height
  // (SemanticStageOptions::counter_min_top_m, LowCounterToTable), and their voxels.
  int low_counter_segments = 0;
  int64_t low_counter_voxels = 0;
  // Views whose room-type descriptor was measured against the training views (RoomTypeProbabilities), those
  // farther than the familiar distance, and the sum of the weights their room evidence kept
  // (1 - DiscountUnfamiliarRoomView; 1 each with SemanticStageOptions::room_view_familiarity off).
  int room_views_measured = 0, room_views_unfamiliar = 0;
  double room_view_weight_sum = 0;
  double familiar_distance = 0;                        // SegmentClassifier::familiar_distance (NaN: forest).
  // Pixels of the views the built-in per-view classifier labelled, and those of superpixels unlike every
  // training superpixel (ViewClassification::unfamiliarity above 1); both 0 with an ONNX object model.
  int64_t view_pixels = 0, unfamiliar_view_pixels = 0;
  double seconds_depth = 0, seconds_selection = 0, seconds_classify = 0, seconds_segments = 0;
};

class SemanticEvidenceBuilder {
 public:
  // Selects the CRF's voxels of `map`. `map`, `renderer` and `models` must outlive the builder.
  static Result<std::unique_ptr<SemanticEvidenceBuilder>> Create(const VoxelMap& map, const ViewRenderer& renderer,
                                                                 const SemanticStageOptions& options, const SemanticModels& models);
  ~SemanticEvidenceBuilder();
  // Optional: the user's ONNX networks replace the built-in per-view classifier and room-type evidence.
  void SetOnnxModels(const OnnxModels* models);
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
  // The evidence, with the object segments of the map classified by shape (when there is a segment model).
  SemanticEvidence Finish() &&;

 private:
  struct Impl;
  explicit SemanticEvidenceBuilder(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semvox
