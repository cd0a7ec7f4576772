#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>

#include <sys/resource.h>

#include "apps/commands.h"
#include "apps/models_dir.h"
#include "apps/onnx_stage.h"
#include "apps/room_types_stage.h"
#include "apps/semantic_stage.h"
#include "objects/support_stage.h"
#include "report/report.h"
#include "core/file_util.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/load_scene.h"
#include "mapping/occupancy_map.h"
#include "mapping/octomap_io.h"
#include "mapping/outliers.h"
#include "mapping/scene_frame.h"
#include "mapping/voxelizer.h"
#include "rooms/floor_plan.h"
#include "rooms/room_export.h"
#include "rooms/room_segmentation.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }
// CPU seconds (user + system) of all threads of this process so far.
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// An output directory inside the input's own directory tree is fine; the input file itself must not be
// overwritten by an output.
Status CheckOutputNotInput(const std::string& input, const std::string& outdir) {
  std::error_code ec;
  const fs::path in = fs::weakly_canonical(input, ec);
  const fs::path out = fs::weakly_canonical(outdir, ec);
  if (!ec && in == out) return Status::InvalidInput(FileError(outdir, "output directory is the input file", "choose another -o"));
  return Status::Ok();
}
}  // namespace

Status RunPipeline(const RunArgs& args) {
  const auto t_all = Clock::now();
  const double c_all = CpuSeconds();
  PipelineConfig config;
  if (!args.config_path.empty()) SEMVOX_RETURN_IF_ERROR(LoadConfigFile(args.config_path, &config));
  if (!args.up.empty()) config.load.up = args.up == "y" ? UpAxis::kY : args.up == "z" ? UpAxis::kZ : UpAxis::kAuto;
  if (args.scale > 0) config.load.scale = args.scale;
  if (args.max_voxels > 0) config.voxelize.max_voxels = size_t(args.max_voxels);
  SEMVOX_RETURN_IF_ERROR(CheckConfig(config));
  SEMVOX_RETURN_IF_ERROR(CheckOutputNotInput(args.input, args.outdir));
  // Only the semantic stage (and the support / clutter and room-type stages after it) reads models.
  std::string models_dir;
  if (config.semantic.enabled) {
    Result<std::string> dir = ResolveModelsDir(args.models_dir, args.argv0);
    if (!dir.ok()) return dir.status();
    models_dir = std::move(dir).value();
  }
  // Fail on an unwritable OUTDIR before any work.
  SEMVOX_RETURN_IF_ERROR(EnsureWritableDirectory(args.outdir));

  nlohmann::ordered_json timing;
  // CPU seconds per stage beside the wall seconds: cpu / wall near the core count means the stage uses them all.
  nlohmann::ordered_json cpu_timing;
  double c0 = 0;
  ProgressReporter progress(GetLogLevel() > LogLevel::kInfo ? ProgressMode::kQuiet : ProgressMode::kAuto);
  auto t0 = Clock::now();
  c0 = CpuSeconds();
  progress.Begin("load");
  Result<Scene> scene_or = LoadScene(args.input, config.load);
  if (!scene_or.ok()) return scene_or.status();
  Scene& scene = scene_or.value();
  const OutlierReport outliers = TrimOutliers(&scene);
  if (outliers.removed_vertices > 0)
    SEMVOX_WARN(args.input << ": trimmed " << outliers.removed_vertices
                           << (scene.is_mesh() ? " vertices (" + std::to_string(outliers.removed_faces) + " faces)" : " points")
                           << " lying far outside the scan (kept box " << outliers.kept_box.min.transpose() << " .. "
                           << outliers.kept_box.max.transpose() << " m)");
  if (scene.is_mesh() ? scene.mesh.faces.empty() : scene.cloud.points.empty())
    return Status::InvalidInput(FileError(args.input, "no geometry left after trimming outliers", "check the units"));
  const Aabb input_box = scene.Bounds();  // Input frame, after trimming.
  // Canonical frame (mapping/scene_frame.h): level, walls along the axes, floor at z = 0. Every stage below
  // works in it; coordinate outputs go back to the input frame through input_from_world.
  SceneFrame frame;
  bool frame_applied = false;
  if (config.load.canonical_frame) {
    SceneFrameOptions fo;
    fo.bin_m = config.voxelize.voxel_size_m;
    fo.horizontal_normal_deg = config.voxelize.horizontal_normal_deg;
    fo.min_floor_to_ceiling_m = config.voxelize.min_floor_to_ceiling_m;
    fo.cloud_normal_neighbors = config.voxelize.cloud_normal_neighbors;
    std::string error;
    if (!fo.Check(&error)) return Status::InvalidInput("configuration: " + error);
    frame = EstimateSceneFrame(scene, fo);
    for (const std::string& w : frame.warnings) SEMVOX_WARN(w);
    if (!frame.identity()) {
      TransformScene(frame.canonical_from_input, &scene);
      frame_applied = true;
    }
    timing["frame"] = frame.seconds;
    SEMVOX_INFO("frame: tilt " << frame.tilt_deg << " deg, yaw " << frame.yaw_deg << " deg, floor z " << frame.floor_z
                               << " m" << (frame_applied ? " (applied)" : " (identity)"));
  }
  const Eigen::Isometry3d input_from_world = frame_applied ? frame.input_from_canonical() : Eigen::Isometry3d::Identity();
  // Heights (floor, ceiling, camera) in the input frame: z of the canonical point above the origin.
  auto input_z = [&](double z) { return frame_applied ? (input_from_world * Eigen::Vector3d(0, 0, z)).z() : z; };
  timing["load"] = Seconds(t0);
  cpu_timing["load"] = CpuSeconds() - c0;
  progress.End();
  SEMVOX_INFO("loaded " << args.input << ": "
                        << (scene.is_mesh() ? std::to_string(scene.mesh.faces.size()) + " triangles"
                                            : std::to_string(scene.cloud.points.size()) + " points"));

  t0 = Clock::now();

  c0 = CpuSeconds();
  progress.Begin("voxelize");
  Result<VoxelMap> map_or = Voxelize(scene, config.voxelize, progress.Callback());
  if (!map_or.ok()) return map_or.status();
  progress.End();
  const VoxelMap& map = map_or.value();
  timing["voxelize"] = Seconds(t0);
  cpu_timing["voxelize"] = CpuSeconds() - c0;
  timing["voxelize_surface"] = map.seconds_surface;
  timing["voxelize_free_space"] = map.seconds_free_space;
  const auto counts = map.grid.CountStates();
  SEMVOX_INFO("voxelised at " << config.voxelize.voxel_size_m << " m: " << counts[2] << " occupied, " << counts[1]
                              << " free, " << counts[0] << " unknown; " << map.scan_positions.size()
                              << " scan positions (" << map.pocket_positions << " in pockets the grid missed); floor z = " << map.floor_z << ", ceiling z = " << map.ceiling_z);

  // ---- render stage: viewpoints and virtual views -> views.json [, views/*.png] ----
  t0 = Clock::now();
  c0 = CpuSeconds();
  progress.Begin("render");
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene, config.render.Raycaster());
  if (!renderer.ok()) return renderer.status();
  ViewsStageSummary views;
  views.seconds_build = Seconds(t0);
  // The semantic stage gathers depth evidence from every kept view as it is rendered.
  std::unique_ptr<SemanticStage> semantic;
  // ... and the support / clutter stage sees every classification view.
  std::unique_ptr<SupportClutterStage> support;
  if (config.semantic.enabled) {
    SemanticStageOptions semantic_options = config.semantic;
    semantic_options.view_selection = ResolveViewSelection(semantic_options.view_selection, scene);
    if (semantic_options.crf_model == VoxelCrfModelChoice::kAuto) {
      semantic_options.crf_model = FlatColouredMesh(scene.mesh) ? VoxelCrfModelChoice::kMesh : VoxelCrfModelChoice::kCloud;
      SEMVOX_INFO("voxel CRF weights: " << VoxelCrfModelChoiceName(semantic_options.crf_model)
                                        << (semantic_options.crf_model == VoxelCrfModelChoice::kMesh ? " (a flat-coloured mesh)"
                                            : scene.is_mesh() ? " (a mesh with scanned, textured or no colours)" : " (a point cloud)"));
    }
    Result<std::unique_ptr<SemanticStage>> st = SemanticStage::Create(map, renderer.value(), semantic_options, models_dir);
    if (!st.ok()) return st.status();
    semantic = std::move(st).value();
    if (args.onnx) semantic->SetOnnxModels(args.onnx.get());
    if (config.objects.enabled) {
      SupportStageOptions so = config.objects;
      so.fusion.voxel_size_m = config.voxelize.voxel_size_m;
      Result<std::unique_ptr<SupportClutterStage>> sup = SupportClutterStage::Create(so, models_dir);
      if (!sup.ok()) return sup.status();
      support = std::move(sup).value();
      semantic->SetViewHook([&support](const RenderedView& view, const ViewClassification* classified) -> Result<std::function<Status()>> {
        // In parallel with other views; the proposals' NYU-4 classifier reuses the view's segmentation.
        Result<SupportClutterStage::ViewResult> r = support->Process(view, classified);
        if (!r.ok()) return r.status();
        return std::function<Status()>([&support, &view, r = std::make_shared<SupportClutterStage::ViewResult>(std::move(r).value())] {
          return support->Add(view, std::move(*r));  // Fused in view order.
        });
      });
    }
  }
  SEMVOX_RETURN_IF_ERROR(RunViewsStage(renderer.value(), map, config.render, args.outdir, args.save_views, &views,
                                       semantic ? semantic->DepthSink() : ViewSink{}, input_from_world));
  timing["render"] = Seconds(t0);
  cpu_timing["render"] = CpuSeconds() - c0;
  timing["render_build"] = views.seconds_build;
  timing["render_trace"] = views.seconds_render;
  progress.End();
  // ---- semantic stage: classification views, Voxel-CRF ----
  if (semantic) {
    t0 = Clock::now();
    c0 = CpuSeconds();
    progress.Begin("classify");
    SEMVOX_RETURN_IF_ERROR(semantic->ClassifyViews(views.viewpoints));
    timing["classify"] = Seconds(t0);
    cpu_timing["classify"] = CpuSeconds() - c0;
    progress.End();
    t0 = Clock::now();
    c0 = CpuSeconds();
    progress.Begin("voxel-crf");
    SEMVOX_RETURN_IF_ERROR(semantic->Solve());
    timing["voxel_crf"] = Seconds(t0);
    cpu_timing["voxel_crf"] = CpuSeconds() - c0;
    progress.End();
  }
  // The occupancy the later stages use: the CRF's refined map when it ran.
  const VoxelGrid& final_grid = semantic ? semantic->refined_grid() : map.grid;
  // ---- end render stage ----

  t0 = Clock::now();

  c0 = CpuSeconds();
  const OccupancyMap occ = ComputeOccupancy(final_grid, map.floor_z, config.occupancy);
  // The image stays on the canonical grid; its origin is the lower-left corner's pose in the input frame.
  OccupancyMap occ_out = occ;
  if (frame_applied) {
    const Eigen::Vector3d o = input_from_world * Eigen::Vector3d(occ.origin_x, occ.origin_y, 0.0);
    const Eigen::Vector3d x = input_from_world.linear() * Eigen::Vector3d::UnitX();
    occ_out.origin_x = o.x();
    occ_out.origin_y = o.y();
    occ_out.origin_yaw = std::atan2(x.y(), x.x());
  }
  SEMVOX_RETURN_IF_ERROR(WriteOccupancyMap(occ_out, args.outdir, "occupancy"));
  timing["occupancy"] = Seconds(t0);
  cpu_timing["occupancy"] = CpuSeconds() - c0;
  // ---- rooms stage (src/rooms): floor plan with door openings, geometric room segmentation, and
  // rooms.png / rooms.geojson / rooms.svg on the occupancy grid. Room types stay "unknown" until a
  // room-type classifier exists.
  nlohmann::ordered_json rooms_summary;
  {
    t0 = Clock::now();
    c0 = CpuSeconds();
    progress.Begin("rooms");
    const FloorPlan plan = FloorPlanFromVoxels(final_grid, map.floor_z, map.ceiling_z, occ, config.floor_plan);
    const RoomSegmentation rooms = SegmentRooms(plan, config.rooms);
    nlohmann::ordered_json types_summary;
    ImageU16 room_ids = rooms.room_extent_ids;  // What rooms.png holds, for the semantic exports.
    if (semantic) {
      // Room types: the room-type CRF over the classification views' evidence and the semantic
      // top view; it writes rooms.png / .geojson / .svg with types (split-off areas get new ids).
      std::vector<ViewRoomEvidence> evidence;
      for (const ClassifiedViewRoomEvidence& e : semantic->room_evidence()) {
        ViewRoomEvidence v;
        v.position = e.position;
        v.yaw_rad = e.yaw_rad;
        v.hfov_rad = e.hfov_rad;
        v.max_range_m = e.max_range_m;
        v.p = e.p;
        evidence.push_back(v);
      }
      const ImageU16 topview = SemanticTopView(semantic->semantic_map(), map.grid, map.floor_z, config.occupancy.band_min_above_floor_m,
                                               config.occupancy.band_max_above_floor_m);
      RoomTypeCrfOptions rt = config.room_types;
      if (rt.model_path.empty()) rt.model_path = models_dir + "/room_type_crf.json";
      if (rt.shape_model_path.empty()) rt.shape_model_path = models_dir + "/room_shape.json";
      SEMVOX_RETURN_IF_ERROR(RunRoomTypeStage(plan, rooms, evidence, topview, rt, args.outdir, &types_summary, input_from_world, &room_ids));
    } else {
      SEMVOX_RETURN_IF_ERROR(WriteRoomOutputs(args.outdir, plan, rooms, false, input_from_world));
    }
    timing["rooms"] = Seconds(t0);
    cpu_timing["rooms"] = CpuSeconds() - c0;
    progress.End();
    if (semantic) {
      t0 = Clock::now();
      c0 = CpuSeconds();
      SEMVOX_RETURN_IF_ERROR(semantic->Write(args.outdir, &room_ids, config.occupancy.band_min_above_floor_m,
                                             config.occupancy.band_max_above_floor_m, occ.image, input_from_world));
      if (support) SEMVOX_RETURN_IF_ERROR(support->Write(args.outdir, final_grid, input_from_world));
      timing["semantic_exports"] = Seconds(t0);
      cpu_timing["semantic_exports"] = CpuSeconds() - c0;
    }
    rooms_summary = {{"method", RoomSegmentationMethodName(config.rooms.method)},
                     {"rooms", rooms.num_rooms},
                     {"door_cells", plan.Count(FloorCell::kDoor) - plan.ceiling_step_cells},
                     {"ceiling_step_cells", plan.ceiling_step_cells},
                     {"wall_cells", plan.Count(FloorCell::kWall)},
                     {"clutter_cells", plan.Count(FloorCell::kClutter)},
                     {"files", {"rooms.png", "rooms.geojson", "rooms.svg"}}};
    for (auto& [k, v] : types_summary.items()) rooms_summary[k] = v;
    SEMVOX_INFO("rooms: " << rooms.num_rooms << " (" << plan.Count(FloorCell::kDoor) - plan.ceiling_step_cells
                          << " door cells, " << plan.ceiling_step_cells << " ceiling-step cells, "
                          << RoomSegmentationMethodName(config.rooms.method) << ")");
  }
  // ---- end rooms stage ----
  t0 = Clock::now();
  c0 = CpuSeconds();
  SEMVOX_RETURN_IF_ERROR(WriteOctomapBinary(final_grid, (fs::path(args.outdir) / "map.bt").string()));
  timing["octomap"] = Seconds(t0);
  cpu_timing["octomap"] = CpuSeconds() - c0;
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((fs::path(args.outdir) / "config_used.yaml").string(), DumpConfig(config)));

  const Aabb& box = input_box;
  nlohmann::ordered_json s;
  s["semvox_version"] = "0.1.0";
  s["input"] = {{"path", args.input},
                {"format", scene.format},
                {"kind", scene.is_mesh() ? "mesh" : "cloud"},
                {"vertices", scene.is_mesh() ? scene.mesh.vertices.size() : scene.cloud.points.size()},
                {"faces", scene.mesh.faces.size()},
                {"has_colors", scene.is_mesh() ? scene.mesh.has_vertex_colors() : scene.cloud.has_colors()},
                {"has_texture", scene.mesh.has_texture()},
                {"materials", scene.mesh.materials.size()},
                {"dropped_non_finite", scene.dropped_non_finite},
                {"trimmed_outliers", outliers.removed_vertices}};
  s["bounds"] = {{"min", {box.min.x(), box.min.y(), box.min.z()}}, {"max", {box.max.x(), box.max.y(), box.max.z()}}};
  s["voxel_size_m"] = config.voxelize.voxel_size_m;
  s["grid"] = {{"dims", map.grid.dims()}, {"origin_key", map.grid.origin_key()}};
  s["voxels"] = {{"occupied", counts[2]}, {"free", counts[1]}, {"unknown", counts[0]}};
  s["floor"] = {{"found", map.floor_found}, {"z", input_z(map.floor_z)}};
  s["ceiling"] = {{"found", map.ceiling_found}, {"z", input_z(map.ceiling_z)}};
  if (config.load.canonical_frame) {
    nlohmann::ordered_json m = nlohmann::ordered_json::array();
    const Eigen::Matrix4d t = input_from_world.matrix();
    for (int r = 0; r < 4; ++r) m.push_back({t(r, 0), t(r, 1), t(r, 2), t(r, 3)});
    s["frame"] = {{"applied", frame_applied},
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
                  {"warnings", frame.warnings}};
  }
  nlohmann::json positions = nlohmann::json::array();
  for (const auto& q : map.scan_positions) {
    const Eigen::Vector3d p = frame_applied ? Eigen::Vector3d(input_from_world * q) : q;
    positions.push_back({p.x(), p.y(), p.z()});
  }
  s["scan_positions"] = positions;
  s["pocket_positions"] = map.pocket_positions;  // The last ones of scan_positions.
  s["enclosed"] = map.enclosed;
  s["rays_cast"] = map.rays_cast;
  s["occupancy"] = {{"image", "occupancy.pgm"}, {"width", occ.image.width}, {"height", occ.image.height},
                    {"origin", {occ_out.origin_x, occ_out.origin_y}}, {"origin_yaw_rad", occ_out.origin_yaw}};
  s["rooms"] = rooms_summary;
  s["views"] = {{"file", "views.json"}, {"positions", views.positions}, {"views", views.views}, {"kept", views.kept},
                {"camera_z", input_z(views.camera_z)}, {"surface_voxels", views.surface_voxels},
                {"surface_voxels_seen", views.seen_surface_voxels}};  // render stage
  if (semantic) s["semantic"] = semantic->Summary();
  if (support) {
    const SupportStageSummary ss = support->summary();
    nlohmann::ordered_json files = nlohmann::ordered_json::array({"support_clutter.ply", "support_clutter_topview.png"});
    if (config.objects.proposals) files.push_back("object_proposals.json");
    s["objects"] = {{"views", ss.views}, {"voxels", ss.voxels}, {"support_voxels", ss.support_voxels},
                    {"clutter_voxels", ss.clutter_voxels}, {"proposals", ss.proposals},
                    {"thread_seconds", {{"support_clutter", ss.ms_classify / 1000.0}, {"proposals", ss.ms_proposals / 1000.0}}},
                    {"files", files}};
  }
  s["warnings"] = TakeWarnings();
  timing["total"] = Seconds(t_all);
  cpu_timing["total"] = CpuSeconds() - c_all;
  s["seconds"] = timing;
  s["cpu_seconds"] = cpu_timing;
  const std::string text = s.dump(2) + "\n";
  SEMVOX_RETURN_IF_ERROR(WriteFileAtomic((fs::path(args.outdir) / "summary.json").string(), text));
  // The self-contained HTML report of everything above (src/report).
  ReportSummary report;
  SEMVOX_RETURN_IF_ERROR(WriteReport(args.outdir, config.report, &report));
  // A run without the semantic stage has no voxels.ply: the page says so, no warning needed.
  if (!report.view_3d_absent.empty() && semantic) SEMVOX_WARN("report.html: 3D view not available: " << report.view_3d_absent);
  if (args.json) std::cout << text;
  SEMVOX_INFO("outputs in " << args.outdir << (semantic ? " (report.html, voxels.ply, map.ot, semantic_topview.png, rooms.geojson, occupancy.pgm/.yaml, map.bt, summary.json, ...)"
                                                        : " (report.html, occupancy.pgm/.yaml, rooms.geojson, map.bt, summary.json)"));
  return Status::Ok();
}

}  // namespace semvox
