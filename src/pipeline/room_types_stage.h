// The room-type stage of the pipeline: room types for the segmented rooms from the per-view room-type evidence
// and the semantic top view, by the room-type CRF (rooms/room_type_crf.h).
//
//   Result<RoomTypesStageResult> typed = TypeRooms(plan, rooms, views, topview, options, max_enclosed_unknown_m2);
//   WriteRoomTypeOutputs(*typed, plan, outdir, input_from_world);
//   summary["room_types"] = RoomTypesSummaryJson(*typed);
//
// TypeRooms gives the typed rooms (split-off areas get new ids after the existing ones; rooms.room_extent_ids
// holds what rooms.png will hold, for the exports that follow). WriteRoomTypeOutputs writes OUTDIR/rooms.png
// (room ids), OUTDIR/rooms.geojson (per room: id, type, type_id, type_probabilities, probability, second_type,
// second_type_id, second_probability, area_m2, ceiling_height_m), OUTDIR/rooms.svg and OUTDIR/rooms_types.png
// (the plan coloured by each pixel's most likely type).
// The model is options.model_path and the room-shape model options.shape_model_path (`semvox run` gives the
// files of its models directory, apps/models_dir.h); an empty model_path is an error, an empty
// shape_model_path types the rooms without their shapes.
#pragma once

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/status.h"
#include "rooms/floor_plan.h"
#include "rooms/room_export.h"
#include "rooms/room_segmentation.h"
#include "rooms/room_type_crf.h"
#include "voxelcrf/semantic_map.h"

namespace semvox {

struct RoomTypesStageResult {
  RoomTypeResult result;                    // The CRF's rooms (with split-off areas), assignments, pixel types.
  std::vector<RoomDescription> described;   // Per room: id, type, probabilities, area, ceiling height.
  RoomTypeCrfOptions options;               // As given (model paths, variant, shape weight).
  bool shapes_used = false;                 // The room-shape model was read.
  size_t views = 0;                         // Views of evidence.
};


// After the CRF, unseen pockets of at most `max_enclosed_unknown_m2` that one room encloses join it, with its
// type (JoinEnclosedUnknown; 0 = none).
Result<RoomTypesStageResult> TypeRooms(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<ViewRoomEvidence>& views,
                                       const Image<uint16_t>& topview_labels, const RoomTypeCrfOptions& options,
                                       double max_enclosed_unknown_m2);

Status WriteRoomTypeOutputs(const RoomTypesStageResult& typed, const FloorPlan& plan, const std::string& outdir,
                            const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity());

// summary.json's rooms."room_types" object: method, model, rooms with their types and shapes, seconds.
nlohmann::ordered_json RoomTypesSummaryJson(const RoomTypesStageResult& typed);

// TypeRooms (pockets joined up to RoomSegmentationOptions' default) and WriteRoomTypeOutputs in one; adds
// "room_types" to `summary` (optional), and `room_ids` (optional) receives what rooms.png holds.
Status RunRoomTypeStage(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<ViewRoomEvidence>& views,
                        const Image<uint16_t>& topview_labels, const RoomTypeCrfOptions& options, const std::string& outdir,
                        nlohmann::ordered_json* summary, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity(),
                        ImageU16* room_ids = nullptr);

}  // namespace semvox
