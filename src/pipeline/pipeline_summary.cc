#include "pipeline/pipeline_summary.h"

#include <filesystem>

#include "core/file_util.h"
#include "core/labels.h"
#include "objects/support_stage.h"
#include "pipeline/pipeline.h"
#include "pipeline/semantic_exports.h"

namespace semvox {

namespace {
nlohmann::ordered_json TimesJson(const std::vector<std::pair<std::string, double>>& times, double total) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [name, seconds] : times) j[name] = seconds;
  j["total"] = total;
  return j;
}
}  // namespace

PipelineSummary SummarizePipeline(const PipelineResult& result) { return SummarizePipeline(result, result.seconds, result.warnings); }

PipelineSummary SummarizePipeline(const PipelineResult& r, const StageTimes& seconds, const std::vector<std::string>& warnings) {
  const PipelineConfig& config = r.config;
  const VoxelMap& map = r.map;
  const Eigen::Isometry3d& input_from_world = r.input_from_world;
  // Heights (floor, ceiling, camera) in the input frame: z of the canonical point above the origin.
  auto input_z = [&](double z) { return r.frame_applied ? (input_from_world * Eigen::Vector3d(0, 0, z)).z() : z; };
  PipelineSummary summary;
  nlohmann::ordered_json& s = summary.json;
  s["semvox_version"] = "0.1.0";
  const InputStats& in = r.input;
  s["input"] = {{"path", in.path},
                {"format", in.format},
                {"kind", in.mesh ? "mesh" : "cloud"},
                {"vertices", in.vertices},
                {"faces", in.faces},
                {"has_colors", in.has_colors},
                {"has_texture", in.has_texture},
                {"materials", in.materials},
                {"dropped_non_finite", in.dropped_non_finite},
                {"trimmed_outliers", in.trimmed_outliers}};
  const Aabb& box = in.bounds;
  s["bounds"] = {{"min", {box.min.x(), box.min.y(), box.min.z()}}, {"max", {box.max.x(), box.max.y(), box.max.z()}}};
  s["voxel_size_m"] = config.voxelize.voxel_size_m;
  s["grid"] = {{"dims", map.grid.dims()}, {"origin_key", map.grid.origin_key()}};
  const auto counts = map.grid.CountStates();
  s["voxels"] = {{"occupied", counts[2]}, {"free", counts[1]}, {"unknown", counts[0]}};
  s["floor"] = {{"found", map.floor_found}, {"z", input_z(map.floor_z)}};
  s["ceiling"] = {{"found", map.ceiling_found}, {"z", input_z(map.ceiling_z)}};
  if (config.load.canonical_frame) {
    const SceneFrame& frame = r.frame;
    nlohmann::ordered_json m = nlohmann::ordered_json::array();
    const Eigen::Matrix4d t = input_from_world.matrix();
    for (int row = 0; row < 4; ++row) m.push_back({t(row, 0), t(row, 1), t(row, 2), t(row, 3)});
    s["frame"] = {{"applied", r.frame_applied},
                  {"input_from_canonical", m},
                  {"up", {frame.up.x(), frame.up.y(), frame.up.z()}},
                  {"up_found", frame.up_found},
                  {"tilt_deg", frame.tilt_deg},
                  {"levelled", frame.levelled},
                  {"upside_down", frame.upside_down},
                  {"yaw_deg", frame.yaw_deg},
                  {"yaw_found", frame.yaw_found},
                  {"floor_z_input", frame.floor_z},
                  {"floor_found", frame.floor_found},
                  {"shift_xy", {frame.shift.x(), frame.shift.y()}},
                  {"warnings", frame.warnings}};
  }
  nlohmann::json positions = nlohmann::json::array();
  for (const auto& q : map.scan_positions) {
    const Eigen::Vector3d p = r.frame_applied ? Eigen::Vector3d(input_from_world * q) : q;
    positions.push_back({p.x(), p.y(), p.z()});
  }
  s["scan_positions"] = positions;
  s["pocket_positions"] = map.pocket_positions;  // The last ones of scan_positions.
  s["enclosed"] = map.enclosed;
  s["rays_cast"] = map.rays_cast;
  s["occupancy"] = {{"image", "occupancy.pgm"}, {"width", r.occupancy.image.width}, {"height", r.occupancy.image.height},
                    {"origin", {r.occupancy_out.origin_x, r.occupancy_out.origin_y}}, {"origin_yaw_rad", r.occupancy_out.origin_yaw}};
  nlohmann::ordered_json rooms = {{"method", RoomSegmentationMethodName(config.rooms.method)},
                                  {"rooms", r.rooms.num_rooms},
                                  {"door_cells", r.plan.Count(FloorCell::kDoor) - r.plan.ceiling_step_cells},
                                  {"ceiling_step_cells", r.plan.ceiling_step_cells},
                                  {"wall_cells", r.plan.Count(FloorCell::kWall)},
                                  {"clutter_cells", r.plan.Count(FloorCell::kClutter)},
                                  {"files", {"rooms.png", "rooms.geojson", "rooms.svg"}}};
  if (r.room_types) rooms["room_types"] = RoomTypesSummaryJson(*r.room_types);
  s["rooms"] = rooms;
  const ViewsStageSummary& views = r.views.summary;
  s["views"] = {{"file", "views.json"}, {"positions", views.positions}, {"views", views.views}, {"kept", views.kept},
                {"camera_z", input_z(views.camera_z)}, {"surface_voxels", views.surface_voxels},
                {"surface_voxels_seen", views.seen_surface_voxels}};
  if (r.labels) {
    s["semantic"] = SemanticSummaryJson(config.semantic, *r.models, *r.evidence, *r.labels);
    if (config.semantic.wall_openings) {
      // Each door and window: its centre on the wall's face and its normal into the room, input frame.
      const double res = map.grid.resolution();
      nlohmann::ordered_json list = nlohmann::ordered_json::array();
      int doors = 0, leaves = 0;
      for (const WallOpening& o : r.labels->openings) {
        doors += o.nyu40 == nyu40::kDoor;
        leaves += o.open_leaf;
        const double a = 0.5 * (o.along0 + o.along1), zc = 0.5 * (o.z0 + o.z1);
        const Eigen::Vector3d c = o.axis == 0 ? map.grid.CellCenter(0, o.line, 0) : map.grid.CellCenter(o.line, 0, 0);
        const Eigen::Vector3d lo = map.grid.CellCenter(0, 0, 0);
        Eigen::Vector3d centre(o.axis == 0 ? lo.x() + a * res : c.x(), o.axis == 0 ? c.y() : lo.y() + a * res, lo.z() + zc * res);
        Eigen::Vector3d normal = o.axis == 0 ? Eigen::Vector3d(0, o.facing, 0) : Eigen::Vector3d(o.facing, 0, 0);
        if (r.frame_applied) centre = input_from_world * centre, normal = input_from_world.linear() * normal;
        list.push_back({{"class", o.nyu40 == nyu40::kDoor ? "door" : "window"},
                        {"centre", {centre.x(), centre.y(), centre.z()}},
                        {"normal", {normal.x(), normal.y(), normal.z()}},
                        {"width_m", o.width_m(res)},
                        {"bottom_m", lo.z() + (o.z0 - 0.5) * res - map.floor_z},
                        {"top_m", lo.z() + (o.z1 + 0.5) * res - map.floor_z},
                        {"open_leaf", o.open_leaf},
                        {"voxels", o.voxels.size()}});
      }
      s["semantic"]["wall_openings"] = {{"doors", doors},
                                        {"windows", int(r.labels->openings.size()) - doors},
                                        {"open_leaves", leaves},
                                        {"relabelled_voxels", r.labels->opening_voxels},
                                        {"openings", list}};
    }
  }
  if (r.objects) {
    const SupportStageSummary ss = r.objects->summary();
    nlohmann::ordered_json files = nlohmann::ordered_json::array({"support_clutter.ply", "support_clutter_topview.png"});
    if (config.objects.proposals) files.push_back("object_proposals.json");
    s["objects"] = {{"views", ss.views}, {"voxels", ss.voxels}, {"support_voxels", ss.support_voxels},
                    {"clutter_voxels", ss.clutter_voxels}, {"proposals", ss.proposals},
                    {"thread_seconds", {{"support_clutter", ss.ms_classify / 1000.0}, {"proposals", ss.ms_proposals / 1000.0}}},
                    {"files", files}};
  }
  s["warnings"] = warnings;
  s["seconds"] = TimesJson(seconds.wall, seconds.total_wall);
  // CPU seconds per stage beside the wall seconds: cpu / wall near the core count means the stage uses them all.
  s["cpu_seconds"] = TimesJson(seconds.cpu, seconds.total_cpu);
  return summary;
}

Status WritePipelineSummary(const PipelineSummary& summary, const std::string& outdir) {
  return WriteFileAtomic((std::filesystem::path(outdir) / "summary.json").string(), summary.Text());
}

}  // namespace semvox
