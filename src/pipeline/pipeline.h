// The pipeline of `semvox run` as a library: scanned mesh or point cloud -> voxel map -> views -> per-voxel
// evidence -> voxel labels -> rooms and room types -> support / clutter and object proposals, every stage's
// result held in memory, and the outputs written apart.
//
//   PipelineOptions options;                  // options.config: every stage's options (pipeline_config.h)
//   options.models_dir = "models";            // resolved by the caller (the CLI: apps/models_dir.h)
//   Result<PipelineResult> run = RunPipeline("scan.ply", options);
//   const SemanticMap& labels = run->labels->map;            // the labelled voxels (with rooms assigned)
//   Status st = WritePipelineOutputs(*run, "out/");           // voxels.ply, map.ot, rooms.geojson, ..., summary.json
//
// The stages, in order (docs/architecture.md has the data-flow table):
//   load       LoadScene, TrimOutliers, the canonical frame (mapping/scene_frame.h)    -> input, frame
//   voxelize   Voxelize (mapping/voxelizer.h)                                          -> map
//   render     RenderViewsStage (views_stage.h); every kept view adds depth evidence   -> views
//   classify   SemanticEvidenceBuilder (semantic_evidence.h), the support / clutter
//              stage on the classification views (objects/support_stage.h)             -> evidence, objects
//   voxel-crf  SolveSemantic (semantic_solve.h)                                        -> labels
//   occupancy  ComputeOccupancy on the refined grid (mapping/occupancy_map.h)          -> occupancy
//   rooms      FloorPlanFromVoxels, SegmentRooms, TypeRooms (room_types_stage.h);
//              the room ids assigned to the labelled voxels                            -> plan, rooms, room_types
// Without the semantic stage (config.semantic.enabled = false) there are no evidence, labels, room types or
// objects, and the rooms are written untyped.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry.h"
#include "core/status.h"
#include "mapping/occupancy_map.h"
#include "mapping/scene_frame.h"
#include "mapping/voxelizer.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/pipeline_summary.h"
#include "pipeline/room_types_stage.h"
#include "pipeline/semantic_evidence.h"
#include "pipeline/semantic_solve.h"
#include "pipeline/views_stage.h"
#include "rooms/floor_plan.h"
#include "rooms/room_segmentation.h"

namespace semvox {

struct OnnxModels;           // pipeline/onnx_stage.h
class SupportClutterStage;   // objects/support_stage.h

struct PipelineOptions {
  PipelineConfig config;  // Every stage's options (the YAML file's sections).
  // The model files (second.*, room_type_knn.bin, voxel_crf*.txt, room_type_crf.json, ...); needed when
  // config.semantic.enabled. The library never looks for models itself.
  std::string models_dir;
  std::shared_ptr<const OnnxModels> onnx;  // Optional: the user's networks (pipeline/onnx_stage.h).
  // Non-empty: a PNG thumbnail of every view is written to thumbnails_outdir/views/ as it is rendered
  // (`semvox run --save-views`; views.json then names them).
  std::string thumbnails_outdir;
};

// The input as loaded, for summary.json's "input" and "bounds".
struct InputStats {
  std::string path, format;
  bool mesh = true;
  size_t vertices = 0, faces = 0, materials = 0;  // Points of a cloud in `vertices`.
  bool has_colors = false, has_texture = false;
  size_t dropped_non_finite = 0, trimmed_outliers = 0;
  Aabb bounds;  // Input frame, after trimming.
};

// Wall and CPU seconds per stage, in the order the stages ran (summary.json's "seconds" and "cpu_seconds").
struct StageTimes {
  std::vector<std::pair<std::string, double>> wall, cpu;
  double total_wall = 0, total_cpu = 0;  // The whole run (and writing), summary.json's "total".
  // Adds to `name`'s seconds (a new entry at the end when absent). cpu < 0: no CPU entry.
  void Add(const std::string& name, double wall_seconds, double cpu_seconds = -1);
};

struct PipelineResult {
  PipelineConfig config;  // As run: the semantic stage's auto choices resolved.
  InputStats input;
  SceneFrame frame;                    // Estimated when config.load.canonical_frame.
  bool frame_applied = false;          // The scene was moved into the canonical frame.
  Eigen::Isometry3d input_from_world = Eigen::Isometry3d::Identity();  // Canonical frame -> input frame.
  VoxelMap map;
  ViewsStageResult views;
  // The semantic stage (absent when disabled).
  std::shared_ptr<const SemanticModels> models;
  std::optional<SemanticEvidence> evidence;
  std::optional<SemanticLabels> labels;  // Rooms assigned (SemanticVoxel::room) from the typed rooms.
  OccupancyMap occupancy;                // On the final grid, canonical frame.
  OccupancyMap occupancy_out;            // The same image, its origin as a pose in the input frame.
  FloorPlan plan;
  RoomSegmentation rooms;                // Geometric segmentation.
  std::optional<RoomTypesStageResult> room_types;  // Typed rooms (split-off areas with new ids).
  std::shared_ptr<SupportClutterStage> objects;   // Support / clutter and proposals (config.objects.enabled).
  StageTimes seconds;
  std::vector<std::string> warnings;     // Logged while running (core/log.h TakeWarnings).

  // The occupancy the later stages use: the CRF's refined map when it ran, else the voxelised one.
  const VoxelGrid& final_grid() const { return labels ? labels->refined : map.grid; }
};

// Runs every stage on the mesh or point cloud at `input` (any format LoadScene reads). Errors name the file or
// the configuration key. Writes nothing unless options.thumbnails_outdir is set.
Result<PipelineResult> RunPipeline(const std::string& input, const PipelineOptions& options);

// Writes the run's outputs into `outdir` (which must exist): occupancy.{pgm,yaml}, views.json, rooms.png /
// .geojson / .svg [/ rooms_types.png], voxels.ply, map.ot, semantic_topview{,_labels}.png, support_clutter.*
// [, object_proposals.json], map.bt and last summary.json (SummarizePipeline, with the writing's seconds and
// warnings). `summary` (optional) receives what summary.json holds.
Status WritePipelineOutputs(const PipelineResult& result, const std::string& outdir, PipelineSummary* summary = nullptr);

}  // namespace semvox
