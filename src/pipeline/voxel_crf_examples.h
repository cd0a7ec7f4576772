// Training-example extraction, the semantic stage's part for `semvox train --voxel-crf` (semvox_pipeline_train):
// ground-truth labels of the CRF's nodes, the layout prior's counts, and the CRF problem of one apartment for
// structural-SVM learning (voxelcrf/voxel_crf_learning.h).
//
//   std::vector<int> gt = GroundTruthNodeLabels(map.grid, evidence, level, nyu40_of_key);
//   AddLayoutCounts(map, evidence, level.num_classes(), gt, &counts);
//   VoxelCrfTrainingExample ex = TrainingExample(map, evidence, crf_options, gt, model);
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mapping/voxelizer.h"
#include "perception/label_levels.h"
#include "pipeline/semantic_evidence.h"
#include "voxelcrf/voxel_crf.h"
#include "voxelcrf/voxel_crf_learning.h"

namespace semvox {

// Per node the ground-truth label (0 empty, k >= 1 class k - 1 of `level`) from NYU40 labels per packed voxel key.
std::vector<int> GroundTruthNodeLabels(const VoxelGrid& grid, const SemanticEvidence& evidence, const LabelLevel& level,
                                       const std::unordered_map<uint64_t, int>& nyu40_of_key);

// Adds the layout-prior counts (LayoutPrior layout, `num_classes` classes) of the ground-truth occupied nodes.
void AddLayoutCounts(const VoxelMap& map, const SemanticEvidence& evidence, int num_classes, const std::vector<int>& gt,
                     std::vector<double>* counts);

// The CRF problem under the ground truth's visibility, for structural-SVM learning.
VoxelCrfTrainingExample TrainingExample(const VoxelMap& map, const SemanticEvidence& evidence, const VoxelCrfOptions& options,
                                        std::vector<int> gt, const VoxelCrfModel& model);

}  // namespace semvox
