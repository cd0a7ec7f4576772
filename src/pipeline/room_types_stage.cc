#include "pipeline/room_types_stage.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "core/labels.h"
#include "core/log.h"
#include "io/image_io.h"

namespace semvox {

Result<RoomTypesStageResult> TypeRooms(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<ViewRoomEvidence>& views,
                                       const Image<uint16_t>& topview_labels, const RoomTypeCrfOptions& options,
                                       double max_enclosed_unknown_m2) {
  const std::string& model_path = options.model_path;
  if (model_path.empty()) return Status::Internal("room types: no model file given (RoomTypeCrfOptions::model_path is empty)");
  Result<RoomTypeModel> model = LoadRoomTypeModel(model_path);
  if (!model.ok()) return model.status();
  // The room-shape model (real plans); when it cannot be read the rooms are typed without their shapes, with a
  // warning; none given: without their shapes.
  std::optional<RoomShapeModel> shapes;
  const std::string& shape_path = options.shape_model_path;
  if (options.shape_weight > 0 && !shape_path.empty()) {
    Result<RoomShapeModel> s = LoadRoomShapeModel(shape_path);
    if (s.ok())
      shapes = *s;
    else
      SEMVOX_WARN("room types: " << s.status().message() << "; rooms typed without their shapes");
  }
  Result<RoomTypeResult> result = InferRoomTypes(plan, rooms, views, topview_labels, *model, options, RoomTypeMethod::kGibbsCrf,
                                                 shapes ? &*shapes : nullptr);
  if (!result.ok()) return result.status();
  RoomTypesStageResult typed;
  typed.options = options;
  typed.shapes_used = shapes.has_value();
  typed.views = views.size();
  typed.result = std::move(result).value();
  JoinEnclosedUnknown(plan, max_enclosed_unknown_m2, &typed.result.rooms.room_extent_ids, &typed.result.pixel_types);
  typed.described = DescribeRooms(plan, typed.result.rooms);
  for (RoomDescription& d : typed.described) {
    if (d.id < 1 || d.id > int(typed.result.assignments.size())) continue;
    const RoomTypeAssignment& a = typed.result.assignments[size_t(d.id - 1)];
    if (a.type_id == 0) continue;  // No evidence at all: stays unknown.
    d.type_id = a.type_id;
    d.type_probability = a.probability;
    d.second_type_id = a.second_type_id;
    d.second_type_probability = a.second_probability;
    d.type_probabilities.assign(kRoomTypeLabels + 1, 0.0);
    for (int y = 0; y < kRoomTypeLabels; ++y) d.type_probabilities[size_t(y + 1)] = std::round(a.probabilities[size_t(y)] * 1e4) / 1e4;
  }
  return typed;
}

Status WriteRoomTypeOutputs(const RoomTypesStageResult& typed, const FloorPlan& plan, const std::string& outdir,
                            const Eigen::Isometry3d& input_from_world) {
  SEMVOX_RETURN_IF_ERROR(WriteRoomOutputs(outdir, plan, typed.result.rooms, typed.described, input_from_world));
  return WriteImage((std::filesystem::path(outdir) / "rooms_types.png").string(), RenderRoomTypes(plan, typed.result.pixel_types));
}

nlohmann::ordered_json RoomTypesSummaryJson(const RoomTypesStageResult& typed) {
  const RoomTypeResult& result = typed.result;
  const RoomTypeCrfOptions& options = typed.options;
  nlohmann::ordered_json j;
  j["method"] = "gibbs_crf";
  j["variant"] = options.variant.Name();
  j["model"] = options.model_path;
  j["shape_model"] = typed.shapes_used ? options.shape_model_path : std::string();
  j["shape_weight"] = typed.shapes_used ? options.shape_weight : 0.0;
  j["adjacency_weight"] = typed.shapes_used ? options.adjacency_weight : 0.0;
  j["fixture_absence_weight"] = options.fixture_absence_weight;
  j["views"] = typed.views;
  j["splits"] = result.splits;
  j["seconds"] = std::round(result.seconds * 1e3) / 1e3;
  j["rooms"] = nlohmann::ordered_json::array();
  for (const RoomDescription& d : typed.described)
    j["rooms"].push_back({{"id", d.id}, {"type_id", d.type_id}, {"probability", std::round(d.type_probability * 1e4) / 1e4},
                          {"second_type_id", d.second_type_id},
                          {"second_probability", std::round(d.second_type_probability * 1e4) / 1e4}});
  // Which evidence decided each room: the CRF's unary terms per type (room_type_crf.h), types named.
  auto terms = [](const std::array<double, kRoomTypeLabels>& t) {
    nlohmann::ordered_json o;
    for (int y = 0; y < kRoomTypeLabels; ++y) o[RoomTypes()[size_t(y + 1)].name] = std::round(t[size_t(y)] * 1e3) / 1e3;
    return o;
  };
  // ... and the shape the room-shape term saw, per input room.
  for (size_t i = 0; i < j["rooms"].size(); ++i) {
    const int id = j["rooms"][i]["id"].get<int>();
    if (id < 1 || id > int(result.assignments.size())) continue;
    const RoomTypeAssignment& a = result.assignments[size_t(id - 1)];
    j["rooms"][i]["terms"] = {{"scene", terms(a.scene_term)}, {"objects", terms(a.object_term)}, {"shape", terms(a.shape_term)},
                              {"fixtures", terms(a.fixture_term)}};
    const int source = a.source_room;
    if (source < 1 || source > int(result.shapes.size())) continue;
    const RoomShape& s = result.shapes[size_t(source - 1)];
    j["rooms"][i]["shape"] = {{"area_m2", std::round(s.area_m2 * 100) / 100}, {"aspect", std::round(s.aspect * 100) / 100},
                              {"fill", std::round(s.fill * 100) / 100}, {"width_m", std::round(s.width_m * 100) / 100},
                              {"connections", s.connections}, {"neighbours", s.neighbours},
                              {"exterior_share", std::round(s.exterior_share * 100) / 100}};
  }
  return j;
}

Status RunRoomTypeStage(const FloorPlan& plan, const RoomSegmentation& rooms, const std::vector<ViewRoomEvidence>& views,
                        const Image<uint16_t>& topview_labels, const RoomTypeCrfOptions& options, const std::string& outdir,
                        nlohmann::ordered_json* summary, const Eigen::Isometry3d& input_from_world, ImageU16* room_ids) {
  Result<RoomTypesStageResult> typed =
      TypeRooms(plan, rooms, views, topview_labels, options, RoomSegmentationOptions().max_enclosed_unknown_m2);
  if (!typed.ok()) return typed.status();
  SEMVOX_RETURN_IF_ERROR(WriteRoomTypeOutputs(*typed, plan, outdir, input_from_world));
  if (room_ids) *room_ids = typed->result.rooms.room_extent_ids;  // What rooms.png holds.
  if (summary) (*summary)["room_types"] = RoomTypesSummaryJson(*typed);
  return Status::Ok();
}

}  // namespace semvox
