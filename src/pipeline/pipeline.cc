#include "pipeline/pipeline.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include <sys/resource.h>
#include <tbb/parallel_invoke.h>
#include <time.h>

#include "core/file_util.h"
#include "core/log.h"
#include "core/progress.h"
#include "io/load_scene.h"
#include "mapping/octomap_io.h"
#include "mapping/outliers.h"
#include "objects/other_labels.h"
#include "objects/support_stage.h"
#include "pipeline/onnx_stage.h"
#include "pipeline/semantic_exports.h"
#include "rooms/room_export.h"

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
// CPU seconds of the calling thread so far.
double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Wall and CPU seconds of one stage, from its construction.
struct StageClock {
  Clock::time_point t0 = Clock::now();
  double c0 = CpuSeconds();
  void AddTo(StageTimes* times, const std::string& name) const { times->Add(name, Seconds(t0), CpuSeconds() - c0); }
};

// Loads the input, trims outliers and moves it into the canonical frame (mapping/scene_frame.h): level, walls
// along the axes, floor at z = 0. Every stage after it works in that frame; coordinate outputs go back to the
// input frame through input_from_world.
Result<Scene> LoadStage(const std::string& input, const PipelineConfig& config, PipelineResult* out) {
  Result<Scene> scene_or = LoadScene(input, config.load);
  if (!scene_or.ok()) return scene_or.status();
  Scene& scene = scene_or.value();
  const OutlierReport outliers = TrimOutliers(&scene);
  if (outliers.removed_vertices > 0)
    SEMVOX_WARN(input << ": trimmed " << outliers.removed_vertices
                      << (scene.is_mesh() ? " vertices (" + std::to_string(outliers.removed_faces) + " faces)" : " points")
                      << " lying far outside the scan (kept box " << outliers.kept_box.min.transpose() << " .. "
                      << outliers.kept_box.max.transpose() << " m)");
  if (scene.is_mesh() ? scene.mesh.faces.empty() : scene.cloud.points.empty())
    return Status::InvalidInput(FileError(input, "no geometry left after trimming outliers", "check the units"));
  InputStats& in = out->input;
  in.path = input;
  in.format = scene.format;
  in.mesh = scene.is_mesh();
  in.vertices = scene.is_mesh() ? scene.mesh.vertices.size() : scene.cloud.points.size();
  in.faces = scene.mesh.faces.size();
  in.has_colors = scene.is_mesh() ? scene.mesh.has_vertex_colors() : scene.cloud.has_colors();
  in.has_texture = scene.mesh.has_texture();
  in.materials = scene.mesh.materials.size();
  in.dropped_non_finite = scene.dropped_non_finite;
  in.trimmed_outliers = outliers.removed_vertices;
  in.bounds = scene.Bounds();
  if (config.load.canonical_frame) {
    SceneFrameOptions fo;
    fo.bin_m = config.voxelize.voxel_size_m;
    fo.horizontal_normal_deg = config.voxelize.horizontal_normal_deg;
    fo.min_floor_to_ceiling_m = config.voxelize.min_floor_to_ceiling_m;
    fo.cloud_normal_neighbors = config.voxelize.cloud_normal_neighbors;
    std::string error;
    if (!fo.Check(&error)) return Status::InvalidInput("configuration: " + error);
    out->frame = EstimateSceneFrame(scene, fo);
    for (const std::string& w : out->frame.warnings) SEMVOX_WARN(w);
    if (!out->frame.identity()) {
      TransformScene(out->frame.canonical_from_input, &scene);
      out->frame_applied = true;
    }
    out->seconds.Add("frame", out->frame.seconds);
    SEMVOX_INFO("frame: tilt " << out->frame.tilt_deg << " deg, yaw " << out->frame.yaw_deg << " deg, floor z " << out->frame.floor_z
                               << " m" << (out->frame_applied ? " (applied)" : " (identity)"));
  }
  out->input_from_world = out->frame_applied ? out->frame.input_from_canonical() : Eigen::Isometry3d::Identity();
  return scene_or;
}

// The semantic stage's auto choices for `scene`: view selection and Voxel-CRF weights.
SemanticStageOptions ResolveSemanticOptions(const SemanticStageOptions& options, const Scene& scene) {
  SemanticStageOptions resolved = options;
  resolved.view_selection = ResolveViewSelection(resolved.view_selection, scene);
  if (resolved.crf_model == VoxelCrfModelChoice::kAuto) {
    resolved.crf_model = FlatColouredMesh(scene.mesh) ? VoxelCrfModelChoice::kMesh : VoxelCrfModelChoice::kCloud;
    SEMVOX_INFO("voxel CRF weights: " << VoxelCrfModelChoiceName(resolved.crf_model)
                                      << (resolved.crf_model == VoxelCrfModelChoice::kMesh ? " (a flat-coloured mesh)"
                                          : scene.is_mesh() ? " (a mesh with scanned, textured or no colours)" : " (a point cloud)"));
  }
  return resolved;
}

// The rooms stage: floor plan with door openings, geometric room segmentation and, after the semantic stage,
// the room types (the room-type CRF over the classification views' evidence and the semantic top view), whose
// room ids go to the labelled voxels.
Status RoomsStage(const std::string& models_dir, PipelineResult* r) {
  const PipelineConfig& config = r->config;
  r->plan = FloorPlanFromVoxels(r->final_grid(), r->map.floor_z, r->map.ceiling_z, r->occupancy, config.floor_plan);
  r->rooms = SegmentRooms(r->plan, config.rooms);
  if (!r->labels) {  // Untyped rooms: the unseen pockets join them now.
    JoinEnclosedUnknown(r->plan, config.rooms.max_enclosed_unknown_m2, &r->rooms.room_extent_ids);
    return Status::Ok();
  }
  const ImageU16 topview = SemanticTopView(r->labels->map, r->map.grid, r->map.floor_z, config.occupancy.band_min_above_floor_m,
                                           config.occupancy.band_max_above_floor_m, config.room_types.min_object_confidence);
  RoomTypeCrfOptions rt = config.room_types;
  if (rt.model_path.empty()) rt.model_path = models_dir + "/room_type_crf.json";
  if (rt.shape_model_path.empty()) rt.shape_model_path = models_dir + "/room_shape.json";
  Result<RoomTypesStageResult> typed =
      TypeRooms(r->plan, r->rooms, r->evidence->rooms, topview, rt, config.rooms.max_enclosed_unknown_m2);
  if (!typed.ok()) return typed.status();
  r->room_types = std::move(typed).value();
  // What rooms.png holds (split-off areas with their new ids).
  AssignRooms(r->room_types->result.rooms.room_extent_ids, r->map.grid, &r->labels->map);
  if (config.semantic.bar_tables) ApplyBarTables(r->map, r->evidence->segmentation.get(), &*r->labels);
  return Status::Ok();
}
}  // namespace

void StageTimes::Add(const std::string& name, double wall_seconds, double cpu_seconds) {
  auto add = [&name](std::vector<std::pair<std::string, double>>* v, double s) {
    for (auto& [n, t] : *v)
      if (n == name) return void(t += s);
    v->emplace_back(name, s);
  };
  add(&wall, wall_seconds);
  if (cpu_seconds >= 0) add(&cpu, cpu_seconds);
}

Result<PipelineResult> RunPipeline(const std::string& input, const PipelineOptions& options) {
  const StageClock all;
  PipelineResult r;
  r.config = options.config;
  const PipelineConfig& config = r.config;
  SEMVOX_RETURN_IF_ERROR(CheckConfig(config));
  if (config.semantic.enabled && options.models_dir.empty())
    return Status::InvalidInput("the semantic stage needs a models directory (PipelineOptions::models_dir; hint: --models DIR)");
  ProgressReporter progress(GetLogLevel() > LogLevel::kNote ? ProgressMode::kQuiet : ProgressMode::kAuto);

  // ---- load ----
  StageClock clock;
  progress.Begin("load");
  Result<Scene> scene_or = LoadStage(input, config, &r);
  if (!scene_or.ok()) return scene_or.status();
  const Scene& scene = scene_or.value();
  clock.AddTo(&r.seconds, "load");
  progress.End();
  SEMVOX_INFO("loaded " << input << ": "
                        << (scene.is_mesh() ? std::to_string(scene.mesh.faces.size()) + " triangles"
                                            : std::to_string(scene.cloud.points.size()) + " points"));

  // ---- voxelize ----
  clock = StageClock();
  progress.Begin("voxelize");
  Result<VoxelMap> map_or = Voxelize(scene, config.voxelize, progress.Callback());
  if (!map_or.ok()) return map_or.status();
  progress.End();
  r.map = std::move(map_or).value();
  const VoxelMap& map = r.map;
  clock.AddTo(&r.seconds, "voxelize");
  r.seconds.Add("voxelize_surface", map.seconds_surface);
  r.seconds.Add("voxelize_free_space", map.seconds_free_space);
  const auto counts = map.grid.CountStates();
  SEMVOX_INFO("voxelised at " << config.voxelize.voxel_size_m << " m: " << counts[2] << " occupied, " << counts[1] << " free, "
                              << counts[0] << " unknown; " << map.scan_positions.size() << " scan positions (" << map.pocket_positions
                              << " in pockets the grid missed); floor z = " << map.floor_z << ", ceiling z = " << map.ceiling_z);

  // ---- render: viewpoints and virtual views; the semantic stage gathers depth evidence from every kept view ----
  clock = StageClock();
  progress.Begin("render");
  Result<ViewRenderer> renderer = ViewRenderer::Create(scene, config.render.Raycaster());
  if (!renderer.ok()) return renderer.status();
  const double seconds_build = Seconds(clock.t0);
  std::unique_ptr<SemanticEvidenceBuilder> semantic;
  if (config.semantic.enabled) {
    r.config.semantic = ResolveSemanticOptions(config.semantic, scene);
    Result<SemanticModels> models = SemanticModels::Load(options.models_dir, config.semantic.crf_model);
    if (!models.ok()) return models.status();
    r.models = std::make_shared<const SemanticModels>(std::move(models).value());
    Result<std::unique_ptr<SemanticEvidenceBuilder>> builder = SemanticEvidenceBuilder::Create(map, renderer.value(), config.semantic, *r.models);
    if (!builder.ok()) return builder.status();
    semantic = std::move(builder).value();
    if (options.onnx) semantic->SetOnnxModels(options.onnx.get());
    // ... and the support / clutter stage sees the classification views.
    if (config.objects.enabled) {
      SupportStageOptions so = config.objects;
      so.fusion.voxel_size_m = config.voxelize.voxel_size_m;
      Result<std::unique_ptr<SupportClutterStage>> support = SupportClutterStage::Create(so, options.models_dir);
      if (!support.ok()) return support.status();
      r.objects = std::move(support).value();
      semantic->SetViewHook([support = r.objects.get()](const RenderedView& view, const ViewClassification* classified)
                                -> Result<std::function<Status()>> {
        // In parallel with other views; the proposals' NYU-4 classifier reuses the view's segmentation.
        Result<SupportClutterStage::ViewResult> result = support->Process(view, classified);
        if (!result.ok()) return result.status();
        return std::function<Status()>(
            [support, &view, result = std::make_shared<SupportClutterStage::ViewResult>(std::move(result).value())] {
              return support->Add(view, std::move(*result));  // Fused in view order.
            });
      });
    }
  }
  Result<ViewsStageResult> views = RenderViewsStage(renderer.value(), map, config.render, options.thumbnails_outdir,
                                                    semantic ? semantic->DepthSink() : ViewSink{});
  if (!views.ok()) return views.status();
  r.views = std::move(views).value();
  r.views.summary.seconds_build = seconds_build;
  clock.AddTo(&r.seconds, "render");
  r.seconds.Add("render_build", r.views.summary.seconds_build);
  r.seconds.Add("render_trace", r.views.summary.seconds_render);
  progress.End();

  // ---- semantic stage: classification views, Voxel-CRF ----
  if (semantic) {
    clock = StageClock();
    progress.Begin("classify");
    SEMVOX_RETURN_IF_ERROR(semantic->ClassifyViews(r.views.summary.viewpoints));
    clock.AddTo(&r.seconds, "classify");
    progress.End();
    clock = StageClock();
    progress.Begin("voxel-crf");
    r.evidence = std::move(*semantic).Finish();
    semantic.reset();
    r.labels.emplace();
    SEMVOX_RETURN_IF_ERROR(SolveSemantic(map, *r.evidence, r.models->crf, config.semantic.crf, &*r.labels));
    if (config.semantic.floor_surface) ApplyFloorSurface(map, config.semantic.floor_surface_margin_m, &*r.labels);
    if (config.semantic.other_labels && r.models->other)
      ApplyOtherLabels(map, *r.evidence, r.models->crf, *r.models->other, kOtherMinVoxels, &*r.labels);
    if (config.semantic.item_labels && r.models->items) ApplyItemLabels(map, *r.evidence, *r.models->items, kOtherMinVoxels, &*r.labels);
    if (config.semantic.wall_openings) ApplyWallOpenings(map, WallOpeningOptions{}, &*r.labels);
    if (config.semantic.furniture_feet) ApplyFurnitureFeet(map, &*r.labels);
    clock.AddTo(&r.seconds, "voxel_crf");
    progress.End();
  }

  // ---- occupancy: the top-view image of the final grid ----
  clock = StageClock();
  r.occupancy = ComputeOccupancy(r.final_grid(), map.floor_z, config.occupancy);
  // The image stays on the canonical grid; its origin is the lower-left corner's pose in the input frame.
  r.occupancy_out = r.occupancy;
  if (r.frame_applied) {
    const Eigen::Vector3d o = r.input_from_world * Eigen::Vector3d(r.occupancy.origin_x, r.occupancy.origin_y, 0.0);
    const Eigen::Vector3d x = r.input_from_world.linear() * Eigen::Vector3d::UnitX();
    r.occupancy_out.origin_x = o.x();
    r.occupancy_out.origin_y = o.y();
    r.occupancy_out.origin_yaw = std::atan2(x.y(), x.x());
  }
  clock.AddTo(&r.seconds, "occupancy");

  // ---- rooms ----
  clock = StageClock();
  progress.Begin("rooms");
  SEMVOX_RETURN_IF_ERROR(RoomsStage(options.models_dir, &r));
  clock.AddTo(&r.seconds, "rooms");
  progress.End();
  SEMVOX_INFO("rooms: " << r.rooms.num_rooms << " (" << r.plan.Count(FloorCell::kDoor) - r.plan.ceiling_step_cells << " door cells, "
                        << r.plan.ceiling_step_cells << " ceiling-step cells, " << RoomSegmentationMethodName(config.rooms.method) << ")");
  r.warnings = TakeWarnings();
  r.seconds.total_wall = Seconds(all.t0);
  r.seconds.total_cpu = CpuSeconds() - all.c0;
  return r;
}

Status WritePipelineOutputs(const PipelineResult& result, const std::string& outdir, PipelineSummary* summary_out) {
  const StageClock all;
  const PipelineConfig& config = result.config;
  const Eigen::Isometry3d& input_from_world = result.input_from_world;
  StageTimes times = result.seconds;
  StageClock clock;
  SEMVOX_RETURN_IF_ERROR(WriteOccupancyMap(result.occupancy_out, outdir, "occupancy"));
  clock.AddTo(&times, "occupancy");
  clock = StageClock();
  SEMVOX_RETURN_IF_ERROR(WriteViewsJson(result.views, config.render, outdir, input_from_world));
  clock.AddTo(&times, "render");
  clock = StageClock();
  if (result.room_types)
    SEMVOX_RETURN_IF_ERROR(WriteRoomTypeOutputs(*result.room_types, result.plan, outdir, input_from_world));
  else
    SEMVOX_RETURN_IF_ERROR(WriteRoomOutputs(outdir, result.plan, result.rooms, false, input_from_world));
  clock.AddTo(&times, "rooms");
  // The semantic exports and the binary OctoMap write different files from the same read-only result: both at
  // once (each mostly on one core). Their seconds: wall clock of each, CPU seconds of the thread that ran it.
  Status semantic_status, octomap_status;
  double semantic_wall = 0, semantic_cpu = 0, octomap_wall = 0, octomap_cpu = 0;
  tbb::parallel_invoke(
      [&] {
        if (!result.labels) return;
        const auto t0 = Clock::now();
        const double c0 = ThreadCpuSeconds();
        semantic_status = WriteSemanticExports(outdir, result.map, *result.labels, config.occupancy.band_min_above_floor_m,
                                               config.occupancy.band_max_above_floor_m, result.occupancy.image, input_from_world,
                                               config.semantic.min_confidence);
        if (semantic_status.ok() && result.objects) semantic_status = result.objects->Write(outdir, result.final_grid(), input_from_world);
        semantic_wall = Seconds(t0);
        semantic_cpu = ThreadCpuSeconds() - c0;
      },
      [&] {
        const auto t0 = Clock::now();
        const double c0 = ThreadCpuSeconds();
        octomap_status = WriteOctomapBinary(result.final_grid(), (fs::path(outdir) / "map.bt").string());
        octomap_wall = Seconds(t0);
        octomap_cpu = ThreadCpuSeconds() - c0;
      });
  SEMVOX_RETURN_IF_ERROR(semantic_status);
  SEMVOX_RETURN_IF_ERROR(octomap_status);
  if (result.labels) times.Add("semantic_exports", semantic_wall, semantic_cpu);
  times.Add("octomap", octomap_wall, octomap_cpu);
  std::vector<std::string> warnings = result.warnings;
  for (std::string& w : TakeWarnings()) warnings.push_back(std::move(w));
  times.total_wall += Seconds(all.t0);
  times.total_cpu += CpuSeconds() - all.c0;
  const PipelineSummary summary = SummarizePipeline(result, times, warnings);
  SEMVOX_RETURN_IF_ERROR(WritePipelineSummary(summary, outdir));
  if (summary_out) *summary_out = summary;
  return Status::Ok();
}

}  // namespace semvox
