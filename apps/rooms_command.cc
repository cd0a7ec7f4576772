// `semvox rooms MAP.png --resolution 0.05 [--method NAME] -o OUT`: room segmentation of a plain 2D map.
#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/log.h"
#include "rooms/floor_plan.h"
#include "rooms/room_export.h"
#include "rooms/room_score.h"
#include "rooms/room_segmentation.h"

namespace semvox {

Status RunRooms(const RoomsArgs& args) {
  PipelineConfig config;
  if (!args.config_path.empty()) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(args.config_path, &config));
  if (!args.method.empty() && !ParseRoomSegmentationMethod(args.method, &config.rooms.method)) {
    std::string all;
    for (const auto& n : RoomSegmentationMethodNames()) all += (all.empty() ? "" : ", ") + n;
    return Status::InvalidInput("--method " + args.method + ": unknown method (hint: one of " + all + ")");
  }
  if (!(args.resolution_m > 0))
    return Status::InvalidInput("--resolution = " + std::to_string(args.resolution_m) + ": must be > 0 metres per pixel");
  SEMVOX_RETURN_IF_ERROR(CheckConfig(config));
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));

  Result<Image<uint8_t>> grey = ReadGreyMap(args.map_path);
  if (!grey.ok()) return grey.status();
  const FloorPlan plan = FloorPlanFromImage(grey.value(), args.resolution_m, config.floor_plan);
  if (plan.Count(FloorCell::kFree) == 0)
    return Status::InvalidInput(FileError(args.map_path, "no free pixel (none brighter than " +
                                                             std::to_string(config.floor_plan.free_threshold) + ")",
                                          "maps are 0 occupied, 255 free"));
  const RoomSegmentation rooms = SegmentRooms(plan, config.rooms);
  SEMVOX_RETURN_IF_ERROR(WriteRoomOutputs(args.outdir, plan, rooms));
  SEMVOX_RETURN_IF_ERROR(
      WriteFileAtomic((std::filesystem::path(args.outdir) / "config_used.yaml").string(), DumpConfig(config)));
  SEMVOX_INFO(args.map_path << ": " << rooms.num_rooms << " rooms (" << RoomSegmentationMethodName(config.rooms.method)
                            << ", " << rooms.seconds << " s); outputs in " << args.outdir
                            << " (rooms.png, rooms.geojson, rooms.svg, config_used.yaml)");
  if (!args.ground_truth_path.empty()) {
    Result<Image<uint8_t>> gt_grey = ReadGreyMap(args.ground_truth_path);
    if (!gt_grey.ok()) return gt_grey.status();
    if (gt_grey->width != plan.width() || gt_grey->height != plan.height())
      return Status::InvalidInput(FileError(args.ground_truth_path, "size differs from the map " + args.map_path,
                                            "give the map's _gt_segmentation.png"));
    const RoomScore score = ScoreRooms(rooms.room_ids, GroundTruthRoomsFromImage(gt_grey.value()));
    std::printf("recall %.4f precision %.4f rooms %d ground_truth_rooms %d seconds %.4f\n", score.recall,
                score.precision, score.num_predicted_rooms, score.num_ground_truth_rooms, rooms.seconds);
  }
  return Status::Ok();
}

}  // namespace semvox
