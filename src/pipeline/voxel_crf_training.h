// Voxel-CRF training (semvox_pipeline_train): learns the Voxel-CRF's weights by structural SVM (Kim et al.
// 2013, Sec. 5.2) and its layout prior on generated apartments, and writes MODELS/voxel_crf.txt and
// voxel_crf_report.json (style "cloud": voxel_crf_cloud.txt and voxel_crf_cloud_report.json).
//
// Each training apartment goes through the same stages as `semvox run` (randomised scan as for the per-view
// classifiers (perception/training_data.h, MakeTrainingScan), voxelisation, rendered views with depth
// evidence, classification views with the shipped per-view classifier: pipeline/semantic_evidence.h), so the
// weights are learned on the evidence the pipeline really produces. The ground truth of every CRF node is
// the NYU40 label of the clean mesh's surface in the voxel (second-level class), or empty
// (pipeline/voxel_crf_examples.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

struct VoxelCrfTrainingOptions {
  std::string models_dir = "models";  // Reads the per-view models (second.*, ...) here and writes the CRF model here.
  std::vector<uint64_t> seeds;        // Generator seeds the weights are learned on.
  std::string seeds_text;             // The same as given (for the report).
  // Scans learned on: flat (the generator's meshes; the default), randomised (palettes, textures, simulated clouds), cloud
  // (randomised, all simulated fused clouds; writes voxel_crf_cloud.txt) or mixed (alternating, first flat).
  std::string style = "flat";
  int epochs = 12;                    // Structural-SVM epochs.
  // When >= 0, w_appearance (the per-view evidence) is held at this value instead of learned.
  double appearance_weight = -1;
};

Status TrainVoxelCrf(const VoxelCrfTrainingOptions& options);

}  // namespace semvox
