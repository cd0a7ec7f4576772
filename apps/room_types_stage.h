// The room-type stage of `semvox run`: room types for the segmented rooms from the per-view
// room-type evidence and the semantic top view, by the room-type CRF (rooms/room_type_crf.h).
//
//   RunRoomTypeStage(plan, rooms, views, topview, options, outdir, &summary)
//     writes OUTDIR/rooms.png (room ids; split-off areas get new ids after the existing ones),
//     OUTDIR/rooms.geojson (per room: id, type, type_id, type_probabilities, probability, second_type,
//     second_type_id, second_probability, area_m2, ceiling_height_m), OUTDIR/rooms.svg and
//     OUTDIR/rooms_types.png (the plan coloured by each pixel's most likely type),
//     and adds a "room_types" object to `summary` (method, model, rooms with their types, timings);
//     `room_ids` (optional) receives what rooms.png holds, for the exports that follow.
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
#include "rooms/room_segmentation.h"
#include "rooms/room_type_crf.h"

namespace semvox {

Status RunRoomTypeStage(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<ViewRoomEvidence>& views,
                        const Image<uint16_t>& topview_labels, const RoomTypeCrfOptions& options, const std::string& outdir,
                        nlohmann::ordered_json* summary, const Eigen::Isometry3d& input_from_world = Eigen::Isometry3d::Identity(),
                        ImageU16* room_ids = nullptr);

}  // namespace semvox
