// Training and scoring the object-segment classifier (object_segments.h) on generated apartments
// (library semvox_objects_train).
//
//   SegmentTrainingOptions o;  o.train_seeds = {0, ..., 39};  o.val_seeds = {100, ..., 109};
//   SegmentTrainingSummary s;
//   Result<SegmentClassifier> clf = TrainSegmentClassifier(o, &s);   // second-level classes (training_data.h)
//
// Each apartment is scanned as the randomised training views see it (MakeTrainingScan: a simulated fused
// cloud of random spacing or a mesh with random artefacts), voxelised as `semvox run` does, and segmented;
// a segment's class is the majority second-level class of its voxels in the clean mesh's voxelisation
// (when it covers at least `min_purity` of its labelled voxels and at least a quarter of its voxels have a
// label). The k-NN (k = 10, Eq. 4 of the MST-CRF paper, standardised features) or the random forest
// (`classifier`) learns from the training segments; the summary scores it on the validation segments,
// voxel-weighted.
//
// The same scans teach the fine labels of the "other" class (objects/other_labels.h): every segment holding
// at least `other_min_voxels` voxels whose ground truth is an "other" id (pillow, box, lamp, ...) gives a
// row of OtherFeatures over those voxels, labelled with their most frequent id. And they teach which items on
// top of a segment (other_labels.h, ItemsOnTop) are objects of their own: a group whose most frequent id
// (over at least half its voxels) differs from that of the rest of its segment is a row of that id; one
// that shares it is a row of class 0 (part of the furniture).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"
#include "objects/object_segments.h"
#include "objects/other_labels.h"
#include "objects/random_forest.h"
#include "objects/segment_classifier.h"
#include "perception/knn_unary.h"
#include "perception/training_data.h"
#include "perception/view_classifier.h"

namespace semvox {

struct SegmentTrainingOptions {
  std::vector<uint64_t> train_seeds;
  std::vector<uint64_t> val_seeds;
  TrainingViewsOptions scans = [] {  // Style and scan randomisation of the apartments.
    TrainingViewsOptions o;
    o.style = TrainingStyle::kRandomised;
    return o;
  }();
  SegmentOptions segments;
  double voxel_size_m = 0.05;       // As `semvox run`'s default. > 0.
  double min_purity = 0.5;          // (0, 1].
  int other_min_voxels = kOtherMinVoxels;  // >= 1.
  SegmentClassifierKind classifier = SegmentClassifierKind::kKnn;
  KnnOptions knn;                   // For kKnn.
  RandomForestOptions forest;       // For kForest.
};

struct SegmentTrainingSummary {
  int train_segments = 0, val_segments = 0;
  ConfusionMatrix val_voxels;       // Second-level classes, each segment's voxels counted with its predicted class.
  double val_segment_accuracy = 0;  // Share of validation segments whose argmax is their class.
  double seconds = 0;
  // The fine labels of "other" (when trained): rows, and the validation rows' voxels per NYU40 id.
  int other_train_rows = 0, other_val_rows = 0;
  ConfusionMatrix other_val_voxels;
  // The items on top (when trained): rows, and the validation groups' voxels, class 0 or NYU40 id.
  int item_train_rows = 0, item_val_rows = 0;
  ConfusionMatrix item_val_voxels;
  std::string ToText(const LabelLevel& level) const;
};

// Rows of the "other" and item labellers: kNumOtherFeatures values per row, NYU40 ids (items: 0 for part of
// the furniture), voxel counts.
struct OtherRows {
  std::vector<float> features;
  std::vector<int> ids, voxels;
};

// The labelled segments of one apartment: features (kNumSegmentFeatures per row), second-level classes
// and voxel counts per row; and, when `other` and `items` are given, the rows of the "other" and item
// labellers.
Status LabelledSegments(uint64_t seed, const SegmentTrainingOptions& options, std::vector<float>* features,
                        std::vector<int>* classes, std::vector<int>* voxels, OtherRows* other = nullptr, OtherRows* items = nullptr);

// The segment classifier; with `other` and `items`, also the "other" and item labellers from the same scans
// (k-NN, options.knn).
Result<SegmentClassifier> TrainSegmentClassifier(const SegmentTrainingOptions& options, SegmentTrainingSummary* summary,
                                                 std::optional<OtherLabeller>* other = nullptr,
                                                 std::optional<ItemLabeller>* items = nullptr);

}  // namespace semvox
