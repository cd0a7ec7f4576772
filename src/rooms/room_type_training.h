// Training data for the room-type CRF (library semvox_rooms_train: adds the apartment generator and the
// per-view classifier to semvox_rooms; the CRF itself depends on neither).
//
//   seed --RoomTypeSceneFromApartment--> RoomTypeTrainingScene (plan, rooms, top view, true types; no views)
//   apartments --CountApartmentObjects--> ObjectRoomCounts     (generator ground truth, every object class)
//   r2v plans  --CountR2vFixtures-------> ObjectRoomCounts     (toilet, bathtub, sink, counter only)
//   TrainRoomTypeModel: confusion, statistics, SSVM weights of every variant, dense-CRF parameters.
//
// The plan of a generated apartment is rasterised from its ground truth (no voxelisation: fast, and the
// same for every run): room interiors free, furniture standing on the floor clutter, door openings door
// cells, everything else wall; then segmented with SegmentRooms. The top view is the generator's
// topview_gt raster (hidden cells as 0). The true type of a pixel is its room's type.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/status.h"
#include "perception/knn_unary.h"
#include "perception/training_data.h"
#include "perception/view_classifier.h"
#include "rooms/r2v_plan.h"
#include "rooms/room_type_crf.h"
#include "scenegen/apartment.h"

namespace semvox {

FloorPlan FloorPlanFromApartment(const Apartment& apartment, double resolution_m = 0.05);

// Plan, segmentation (default options), top view and true types of generated apartment `seed` (views empty).
Result<RoomTypeTrainingScene> RoomTypeSceneFromApartment(uint64_t seed, const RoomSegmentationOptions& segmentation = {});
// The same for a given apartment (one built on a real plan, say).
RoomTypeTrainingScene RoomTypeSceneOf(const Apartment& apartment, const RoomSegmentationOptions& segmentation = {});

// Rooms of each type and how many of them hold each NYU40 object class (generator ground truth).
ObjectRoomCounts CountApartmentObjects(const Apartment& apartment);

// R2V plans (../shared/data/r2v/plan_*.txt): rooms flood-filled from their label boxes with walls and doors as
// barriers, typed by room_types.tsv's r2v names; fixtures counted into the room holding their centre
// (cooking_counter -> counter 12, washing_basin -> sink 34, toilet -> 33, bathtub -> 36). Only the first
// `max_plans` sorted plans are read (kR2vTrainingPlans: the validation plans never enter a model). Fails when
// the directory holds no plan.
Result<ObjectRoomCounts> CountR2vFixtures(const std::string& dir, int max_plans, int* plans_used = nullptr);

// Recomputes the R2V fixture rows of `model->object_type` (counter, sink, toilet, bathtub) as
// TrainRoomTypeModel does: generated apartments `statistics_seeds` pooled with the first `r2v_plans` sorted
// plans of `r2v_dir`. The other statistics and the learned terms stay. For a model whose fixture statistics
// counted other plans (`semvox train --room-type-statistics`). `plans_used`: plans that gave rooms.
Status RefreshR2vFixtureStatistics(const std::vector<uint64_t>& statistics_seeds, const std::string& r2v_dir, int r2v_plans,
                                   RoomTypeModel* model, int* plans_used = nullptr);

// Object statistics from the generator counts, with the rows of the R2V fixture classes computed from the
// pooled counts (generator + R2V rooms) when `r2v` is given.
std::vector<std::array<double, kRoomTypeLabels>> CombinedObjectStatistics(const ObjectRoomCounts& generator,
                                                                        const ObjectRoomCounts* r2v);

// Rows of the per-view room-type k-NN (perception/room_evidence.h): the descriptor of the ground-truth
// second-level classes of every training view of a typed room (TrainingViewsOptions{}: flat, as `semvox train`
// builds them), first of the generated apartments `seeds`, then of apartments built on the R2V plans `plans`
// (real layouts with their fixtures, furnished by room type; plan k, in the given order, draws its colours and
// views from kPlanViewSeedBase + k). A plan that cannot be built (no doors, no closed room) is skipped and
// counted. Both cores; the rows come in seed, then plan, then view order whatever the threads.
inline constexpr uint64_t kPlanViewSeedBase = 1000000;
// The training apartment of R2V plan k of a list: its layout built and furnished by room type from seed
// kPlanViewSeedBase + k (the seed its views draw from too). An error when the plan cannot be built.
Result<Apartment> TrainingPlanApartment(const std::string& plan, size_t k);
// Appends the k-NN row of one view (RoomViewDescriptor of `classes`, second-level class indices per pixel) and
// its type index to `x` and `y` when the view shows a typed room; returns whether it did.
bool AddRoomKnnRow(const LabelledView& view, const Image<int32_t>& classes, int num_classes, std::vector<float>* x,
                   std::vector<int>* y);
struct RoomKnnRows {
  std::vector<float> x;  // RoomDescriptorDims(second level) per row.
  std::vector<int> y;    // Room type id - 1.
  int generated_rows = 0, plan_rows = 0, plans_used = 0, plans_skipped = 0;
};
// With `classifier` (the second-level per-view classifier `semvox run` uses), the descriptors are those of its
// predicted classes (union CRF labels, as the pipeline computes a view's room-type evidence), so that the k-NN
// learns what the classifier makes of each room; without it, of the ground-truth classes.
Result<RoomKnnRows> RoomTypeKnnRows(const std::vector<uint64_t>& seeds, const std::vector<std::string>& plans,
                                    const ViewClassifier* classifier = nullptr);

// One classified view: where it looked from, and the room-type descriptor of its predicted classes.
struct RoomViewRecord {
  uint64_t seed = 0;
  ViewRoomEvidence geometry;       // p unset.
  std::vector<float> descriptor;   // RoomViewDescriptor of the predicted second-level classes.
  double object_fraction = 0;
};
RoomViewRecord MakeRoomViewRecord(const LabelledView& view, const Image<int32_t>& predicted_classes, int num_classes,
                                  const std::vector<bool>& object_classes, double max_range_m);

// Per-view evidence of apartment `seed` as the pipeline would compute it: every training view rendered,
// classified (second level, tree CRF) and given to the room-type k-NN.
Result<std::vector<ViewRoomEvidence>> ClassifiedApartmentViews(uint64_t seed, const TrainingViewsOptions& views,
                                                               const ViewClassifier& second_level,
                                                               const KnnClassifier& room_knn, double max_range_m);

// The per-view evidence of a record: its geometry and the room-type k-NN's distribution of its descriptor
// (RoomTypeProbabilities, with `min_object_fraction`).
ViewRoomEvidence RoomViewEvidence(const KnnClassifier& knn, const RoomViewRecord& record, double min_object_fraction);

// A room-type k-NN (KnnOptions{}) over the rows whose apartment is not one of `exclude_seeds`.
Result<KnnClassifier> RoomKnnWithout(const std::vector<float>& room_rows, const std::vector<int>& room_labels,
                                     const std::vector<uint64_t>& room_row_seeds, int descriptor_dims,
                                     const std::vector<uint64_t>& exclude_seeds);

// Every training view of apartment `seed`: with `records`, the record of its predicted second-level classes
// (as ClassifiedApartmentViews); with `truth_rows` and `truth_labels`, the room-type k-NN row of its
// ground-truth classes and its type index (views of a typed room only; as `semvox train`'s k-NN rows).
Status ClassifiedApartmentRecords(uint64_t seed, const TrainingViewsOptions& views, const ViewClassifier& second_level,
                                  double max_range_m, std::vector<RoomViewRecord>* records, std::vector<float>* truth_rows,
                                  std::vector<int>* truth_labels);

// Scenes of apartments built on the R2V plans `plans` (real layouts with their fixtures, furnished by room
// type; plan k, in the given order, draws its colours and views from kPlanViewSeedBase + k, as RoomTypeKnnRows),
// each with the evidence of its training views: classified by `second_level` (tree CRF classes), described
// and given to `room_knn` (RoomViewEvidence with `min_object_fraction`), so that the terms learned on them
// (LearnRoomTypeEvidenceTerms) see what the classifiers make of real layouts. `room_knn` must not hold rows
// of these apartments (the shipped k-NN holds generated apartments only). Plans that cannot be built are
// skipped and counted. Both cores; scenes in plan order.
Result<std::vector<RoomTypeTrainingScene>> PlanEvidenceScenes(const std::vector<std::string>& plans, const ViewClassifier& second_level,
                                                              const KnnClassifier& room_knn, double max_range_m,
                                                              double min_object_fraction, int* skipped = nullptr);

// The same for generated apartments `seeds` (their classified training views; the seeds should be neither
// the per-view classifier's nor `room_knn`'s training apartments, so that the evidence is what a new
// apartment gets). Both cores; scenes in seed order.
Result<std::vector<RoomTypeTrainingScene>> GeneratedEvidenceScenes(const std::vector<uint64_t>& seeds, const ViewClassifier& second_level,
                                                                   const KnnClassifier& room_knn, double max_range_m,
                                                                   double min_object_fraction);

struct RoomTypeTrainingOptions {
  RoomTypeCrfOptions crf;              // Graph options for training.
  SsvmOptions ssvm;
  double min_object_fraction = 0.02;   // As RoomTypeProbabilities.
  std::string r2v_dir;                 // Empty: no R2V statistics.
  int r2v_plans = kR2vTrainingPlans;   // The first this many sorted plans of r2v_dir (the training split).
  // LearnRoomTypeEvidenceTerms: the SSVM direction of each variant is the mean of this many runs (seeds
  // ssvm.seed, ssvm.seed + 1, ...; each normalised so that its largest weight is 1). >= 1.
  int ssvm_runs = 1;
  // ... and the weight scale is chosen with the room-shape term (at crf.shape_weight) when this is set.
  const RoomShapeModel* shapes = nullptr;
};

struct RoomTypeTrainingSummary {
  int evidence_scenes = 0, statistics_apartments = 0, r2v_plans = 0;
  std::string report;  // One line per learned piece.
};

// Learns the model: object statistics from `statistics_seeds` (+ R2V), homogeneity statistics from the same
// apartments' truth, and the confusion, SSVM weights of every variant and dense-CRF parameters from the
// `records` of the evidence apartments, whose per-view distributions come from a k-NN over `room_rows`
// (labels `room_labels`, apartment `room_row_seeds`) without the rows of the view's own apartment
// (leave one apartment out, so no view is its own neighbour).
Result<RoomTypeModel> TrainRoomTypeModel(const std::vector<RoomViewRecord>& records, const std::vector<float>& room_rows,
                                         const std::vector<int>& room_labels, const std::vector<uint64_t>& room_row_seeds,
                                         int descriptor_dims, const std::vector<uint64_t>& statistics_seeds,
                                         const RoomTypeTrainingOptions& options, RoomTypeTrainingSummary* summary);

// One scene per apartment of `records` (first-seen order) with its views' evidence from a k-NN over `room_rows`
// without that apartment's rows. Scenes come from `prepared` when it holds the seed (views replaced), else
// from RoomTypeSceneFromApartment.
Result<std::vector<RoomTypeTrainingScene>> LeaveOneOutEvidenceScenes(const std::vector<RoomViewRecord>& records,
                                                                     const std::vector<float>& room_rows,
                                                                     const std::vector<int>& room_labels,
                                                                     const std::vector<uint64_t>& room_row_seeds,
                                                                     int descriptor_dims, double min_object_fraction,
                                                                     const std::map<uint64_t, RoomTypeTrainingScene>* prepared);

// What TrainRoomTypeModel learns from labelled views, on `scenes` with their views set; the statistics already
// in `model` (objects, homogeneity) are kept: the confusion (Eq. 3), the SSVM weights of `variants` with their
// scale calibration, and the dense-CRF grid search. The scale of each variant's weights is chosen on
// `calibration` when given and not empty (apartments held out of the learning, so that the sampler's
// temperature is not fitted to the scenes the direction came from), else on `scenes`. Returns one report line
// per learned piece.
std::string LearnRoomTypeEvidenceTerms(const std::vector<RoomTypeTrainingScene>& scenes, const std::vector<RoomTypeVariant>& variants,
                                       const RoomTypeTrainingOptions& options, RoomTypeModel* model,
                                       const std::vector<RoomTypeTrainingScene>* calibration = nullptr);

// The variants `semvox train` learns weights for (Table II rows and their phi_cnn counterparts).
std::vector<RoomTypeVariant> AllRoomTypeVariants();

}  // namespace semvox
