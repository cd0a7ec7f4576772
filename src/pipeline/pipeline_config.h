// Every stage's options, one member per section of the YAML file that `semvox run --config` reads
// (apps/config.h parses and dumps it; docs/configuration.md lists the keys).
#pragma once

#include "core/status.h"
#include "io/load_scene.h"
#include "mapping/occupancy_map.h"
#include "mapping/voxelizer.h"
#include "objects/support_stage.h"
#include "pipeline/semantic_options.h"
#include "render/views.h"
#include "report/report.h"
#include "rooms/floor_plan.h"
#include "rooms/room_segmentation.h"
#include "rooms/room_type_crf.h"

namespace semvox {

struct PipelineConfig {
  LoadOptions load;                // Section "input" (io/load_scene.h).
  VoxelizeOptions voxelize;        // Section "mapping" (mapping/voxelizer.h).
  OccupancyOptions occupancy;      // Section "occupancy" (mapping/occupancy_map.h).
  FloorPlanOptions floor_plan;     // Section "rooms": floor plan fields (rooms/floor_plan.h).
  RoomSegmentationOptions rooms;   // Section "rooms": segmentation fields (rooms/room_segmentation.h).
  RoomTypeCrfOptions room_types;   // Section "room_types": the room-type CRF (rooms/room_type_crf.h).
  ViewsOptions render;             // Section "render": viewpoints and virtual views (render/views.h).
  SemanticStageOptions semantic;   // Section "semantic": classification views and the Voxel-CRF (pipeline/semantic_options.h).
  SupportStageOptions objects;     // Section "objects": support / clutter and object proposals (objects/support_stage.h).
  ReportOptions report;            // Section "report": report.html (report/report.h), written by the CLI after the run.
};

// Runs every stage's Check(); the message names the section and key.
Status CheckConfig(const PipelineConfig& config);

}  // namespace semvox
