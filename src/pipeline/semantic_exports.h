// Exports, the last part of the semantic stage: voxels.ply, map.ot, semantic_topview.png and
// semantic_topview_labels.png, and the stage's section of summary.json.
//
//   WriteSemanticExports(outdir, map, labels, band_min_m, band_max_m, occupancy.image, input_from_world);
//   summary["semantic"] = SemanticSummaryJson(options, models, evidence, labels);
#pragma once
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>

#include "core/image.h"
#include "core/status.h"
#include "mapping/voxelizer.h"
#include "pipeline/semantic_evidence.h"
#include "pipeline/semantic_solve.h"

namespace semvox {

// voxels.ply (coordinates mapped by `input_from_world`, the canonical frame back to the input frame), map.ot
// (every known voxel of the refined map; occupied ones with label and confidence) and the top views between
// band_min_m and band_max_m above the floor (both on the grid, canonical frame). Rooms are those already
// assigned to labels.map (AssignRooms).
// Labels under `min_confidence` are written as 0 to map.ot and the top views (voxels.ply keeps them all).
Status WriteSemanticExports(const std::string& outdir, const VoxelMap& map, const SemanticLabels& labels, double band_min_m,
                            double band_max_m, const ImageRgb8& occupancy_image,
                            const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity(), double min_confidence = 0);

// summary.json's "semantic" object: models, views, nodes, iterations, label histogram, seconds, files.
nlohmann::ordered_json SemanticSummaryJson(const SemanticStageOptions& options, const SemanticModels& models,
                                           const SemanticEvidence& evidence, const SemanticLabels& labels);

}  // namespace semvox
