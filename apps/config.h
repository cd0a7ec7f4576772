// The pipeline configuration: every stage's options, read from one YAML file.
//
// The YAML file has one section per stage (input, mapping, occupancy, ...) holding that stage's option
// fields by name. Unknown sections or keys and out-of-range values are errors naming the key and the
// allowed range. The effective configuration is written beside the outputs (config_used.yaml).
#pragma once

#include <string>
#include <vector>

#include "core/option_table.h"
#include "core/status.h"
#include "io/load_scene.h"
#include "mapping/occupancy_map.h"
#include "mapping/voxelizer.h"
#include "rooms/floor_plan.h"
#include "rooms/room_segmentation.h"
#include "rooms/room_type_crf.h"
#include "render/views.h"
#include "apps/semantic_stage.h"
#include "objects/support_stage.h"
#include "report/report.h"

namespace semvox {

struct PipelineConfig {
  LoadOptions load;
  VoxelizeOptions voxelize;
  OccupancyOptions occupancy;
  FloorPlanOptions floor_plan;     // Section "rooms": floor plan fields (rooms/floor_plan.h).
  RoomSegmentationOptions rooms;   // Section "rooms": segmentation fields (rooms/room_segmentation.h).
  RoomTypeCrfOptions room_types;   // Section "room_types": the room-type CRF (rooms/room_type_crf.h).
  ViewsOptions render;  // Section "render": viewpoints and virtual views (render/views.h).
  SemanticStageOptions semantic;  // Section "semantic": classification views and the Voxel-CRF (apps/semantic_stage.h).
  SupportStageOptions objects;    // Section "objects": support / clutter and object proposals (objects/support_stage.h).
  ReportOptions report;           // Section "report": report.html (report/report.h).
};

// One key of the YAML file: its section and the option, from the stage's options table (core/option_table.h).
struct ConfigKey {
  std::string section;
  Option<PipelineConfig> option;
};
// Every key, in the order of `semvox config --dump`.
const std::vector<ConfigKey>& ConfigKeys();

// Applies the settings in `path` on top of `config`.
Status LoadConfigFile(const std::string& path, PipelineConfig* config);
// Same, from YAML text (`name` appears in messages).
Status ParseConfig(const std::string& yaml_text, const std::string& name, PipelineConfig* config);
// Every option with its value and a comment giving units, range and meaning.
std::string DumpConfig(const PipelineConfig& config);
// Runs every stage's Check(); the message names the section and key.
Status CheckConfig(const PipelineConfig& config);

}  // namespace semvox
