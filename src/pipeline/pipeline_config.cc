#include "pipeline/pipeline_config.h"

#include <string>

namespace semvox {

Status CheckConfig(const PipelineConfig& config) {
  std::string error;
  if (!config.load.Check(&error)) return Status::InvalidInput("configuration: input." + error);
  if (!config.voxelize.Check(&error)) return Status::InvalidInput("configuration: mapping." + error);
  if (!config.occupancy.Check(&error)) return Status::InvalidInput("configuration: occupancy." + error);
  if (!config.floor_plan.Check(&error)) return Status::InvalidInput("configuration: rooms." + error);
  if (!config.rooms.Check(&error)) return Status::InvalidInput("configuration: rooms." + error);
  if (!config.room_types.Check(&error)) return Status::InvalidInput("configuration: room_types." + error);
  if (!config.render.Check(&error)) return Status::InvalidInput("configuration: render." + error);
  if (!config.semantic.Check(&error)) return Status::InvalidInput("configuration: semantic." + error);
  if (!config.objects.Check(&error)) return Status::InvalidInput("configuration: objects." + error);
  if (!config.report.Check(&error)) return Status::InvalidInput("configuration: report." + error);
  return Status::Ok();
}

}  // namespace semvox
