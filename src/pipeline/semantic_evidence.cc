#include "pipeline/semantic_evidence.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <type_traits>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/log.h"
#include "objects/object_segments.h"
#include "objects/other_labels.h"
#include "objects/segment_classifier.h"
#include "perception/classifier_views.h"
#include "perception/knn_unary.h"
#include "perception/room_evidence.h"
#include "perception/view_classifier.h"
#include "pipeline/onnx_stage.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }
}  // namespace

Result<SemanticModels> SemanticModels::Load(const std::string& models_dir, VoxelCrfModelChoice crf_model) {
  SemanticModels m;
  m.level = SecondLevel();
  Result<ViewClassifier> clf = ViewClassifier::Load(models_dir + "/second", ViewClassifierOptions{});
  if (!clf.ok())
    return Status::InvalidInput(FileError(models_dir + "/second.*", "cannot load the per-view classifier: " + clf.status().message(),
                                          "pass --models DIR or run `semvox train`"));
  m.classifier = std::make_shared<const ViewClassifier>(std::move(clf).value());
  Result<KnnClassifier> room = KnnClassifier::Load(models_dir + "/room_type_knn.bin");
  if (!room.ok()) return room.status();
  m.room_knn = std::make_shared<const KnnClassifier>(std::move(room).value());
  m.room_familiar_distance = m.room_knn->TrainingNeighbourDistanceQuantile(KnnClassifier::kFamiliarQuantile);
  std::error_code ec;
  Result<std::optional<SegmentClassifier>> seg = SegmentClassifier::LoadFromDirectory(models_dir);
  if (!seg.ok()) return seg.status();
  if (seg->has_value()) {
    if ((*seg)->dims() != kNumSegmentFeatures || (*seg)->num_classes() != m.level.num_classes())
      return Status::InvalidInput(FileError(models_dir + "/" + SegmentClassifierFile((*seg)->kind()),
                                            "not an object-segment model for the second-level classes", "re-run `semvox train`"));
    m.segments = std::make_shared<const SegmentClassifier>(std::move(**seg));
  } else {
    SEMVOX_WARN(models_dir << "/object_segments.knn: not found; the Voxel-CRF runs without the object-segment term (run `semvox train`)");
  }
  // An optional model: loaded when its file exists (a broken file is an error), else a warning saying what is lost.
  auto load_optional = [&](const char* file, auto* out, const char* without) -> Status {
    using Model = typename std::decay_t<decltype(*out)>::element_type;
    const std::string path = models_dir + "/" + file;
    if (!fs::exists(path, ec)) {
      SEMVOX_WARN(path << ": not found; " << without << " (run `semvox train --segments`)");
      return Status::Ok();
    }
    Result<std::remove_const_t<Model>> model = std::remove_const_t<Model>::Load(path);
    if (!model.ok()) return model.status();
    *out = std::make_shared<Model>(std::move(model).value());
    return Status::Ok();
  };
  SEMVOX_RETURN_IF_ERROR(load_optional(kOtherLabellerFile, &m.other, "every voxel labelled \"other\" gets one NYU40 id"));
  SEMVOX_RETURN_IF_ERROR(load_optional(kItemLabellerFile, &m.items, "what lies on furniture keeps the furniture's label"));
  std::string model_path = models_dir + "/voxel_crf.txt";
  if (crf_model == VoxelCrfModelChoice::kCloud) {
    const std::string cloud_path = models_dir + "/voxel_crf_cloud.txt";
    if (fs::exists(cloud_path, ec)) model_path = cloud_path;
    else SEMVOX_WARN(cloud_path << ": not found; the Voxel-CRF uses " << model_path << " (run `semvox train --voxel-crf --voxel-crf-style cloud`)");
  }
  if (fs::exists(model_path, ec)) {
    Result<VoxelCrfModel> loaded = VoxelCrfModel::Load(model_path);
    if (!loaded.ok()) return loaded.status();
    m.crf = std::move(loaded).value();
    m.crf_file = fs::path(model_path).filename().string();
  } else {
    m.crf = VoxelCrfModel::Default(Nyu40OfClasses(m.level), m.level.class_names);
    SEMVOX_WARN(model_path << ": not found; the Voxel-CRF uses untrained default weights (run `semvox train`)");
  }
  if (m.crf.num_classes() != m.level.num_classes())
    return Status::InvalidInput(FileError(model_path, "class count differs from the per-view classifier's", "re-run `semvox train`"));
  return m;
}

struct SemanticEvidenceBuilder::Impl {
  const VoxelMap* map = nullptr;
  const ViewRenderer* renderer = nullptr;
  const SemanticModels* models = nullptr;
  SemanticStageOptions options;
  std::unique_ptr<EvidenceAccumulator> acc;
  SemanticEvidence out;
  const OnnxModels* onnx = nullptr;
  ViewHook hook;
};

SemanticEvidenceBuilder::SemanticEvidenceBuilder(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SemanticEvidenceBuilder::~SemanticEvidenceBuilder() = default;
void SemanticEvidenceBuilder::SetOnnxModels(const OnnxModels* models) { impl_->onnx = models; }
void SemanticEvidenceBuilder::SetViewHook(ViewHook hook) { impl_->hook = std::move(hook); }

Result<std::unique_ptr<SemanticEvidenceBuilder>> SemanticEvidenceBuilder::Create(const VoxelMap& map, const ViewRenderer& renderer,
                                                                                 const SemanticStageOptions& options,
                                                                                 const SemanticModels& models) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("configuration: semantic." + error);
  auto impl = std::make_unique<Impl>();
  impl->map = &map;
  impl->renderer = &renderer;
  impl->models = &models;
  impl->options = options;
  impl->out.nodes = SelectVoxelCrfNodes(map.grid, map.floor_z, map.ceiling_z, options.evidence);
  if (map.exact_surface) MarkSurfaceNodes(&impl->out.nodes);
  else MarkPointNodes(map.point_voxels, &impl->out.nodes);
  impl->acc = std::make_unique<EvidenceAccumulator>(map.grid, impl->out.nodes, models.level.num_classes(), options.evidence);
  SEMVOX_INFO("voxel CRF: " << impl->out.nodes.size() << " nodes (" << impl->out.nodes.count_state(VoxelState::kOccupied) << " occupied, "
                            << impl->out.nodes.count_state(VoxelState::kFree) << " free, " << impl->out.nodes.count_state(VoxelState::kUnknown)
                            << " unknown)");
  return std::unique_ptr<SemanticEvidenceBuilder>(new SemanticEvidenceBuilder(std::move(impl)));
}

ViewSink SemanticEvidenceBuilder::DepthSink() {
  return [this](const ViewRecord& record, const RenderedView& view) {
    if (!record.kept()) return Status::Ok();
    const auto t0 = Clock::now();
    impl_->acc->AddDepthView(view);
    impl_->out.seconds_depth += Seconds(t0);
    return Status::Ok();
  };
}

Status SemanticEvidenceBuilder::ClassifyViews(const std::vector<Eigen::Vector3d>& positions) {
  Impl& s = *impl_;
  const auto t0 = Clock::now();
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(s.options.classify_width, s.options.classify_height, ClassifierViews::kHorizontalFovDeg);
  double z = s.map->floor_z + ClassifierViews::kEyeHeightM;
  if (s.map->ceiling_found) z = std::min(z, s.map->ceiling_z - 0.2);
  struct Pose {
    Eigen::Vector3d p;
    double yaw;
  };
  // Candidates: every viewpoint turned in classify_yaw_step_deg steps.
  std::vector<Pose> poses;
  const int per_position = int(std::lround(360.0 / s.options.classify_yaw_step_deg));
  for (const auto& p : positions)
    for (int k = 0; k < per_position; ++k) poses.push_back({Eigen::Vector3d(p.x(), p.y(), z), k * s.options.classify_yaw_step_deg});
  const RenderOptions render{s.map->grid.resolution(), 100.0};
  s.out.selection = ViewSelection{};
  s.out.selection.candidates = poses.size();
  // Per candidate: whether the view hook sees it (every classified view, or only the cover's).
  std::vector<char> to_hook(poses.size(), 1);
  const bool cover = s.options.view_selection == ClassifyViewSelection::kCover ||
                     s.options.view_selection == ClassifyViewSelection::kAllObjectsOnCover;
  if (cover && !poses.empty()) {
    // The views that add evidence: candidates the classifier would skip are left out of the cover.
    const auto ts = Clock::now();
    std::vector<Eigen::Isometry3d> world_from_camera;
    for (const Pose& pose : poses) world_from_camera.push_back(WorldFromCameraYawPitch(pose.p, pose.yaw, ClassifierViews::kPitchDeg));
    const std::vector<uint32_t> surface = SurfaceVoxels(s.map->grid);
    std::vector<CandidateVisibility> vis =
        MeasureCandidateVisibility(*s.renderer, s.map->grid, surface, camera, world_from_camera, render, s.options.selection);
    std::vector<std::vector<uint32_t>> seen(vis.size());
    for (size_t c = 0; c < vis.size(); ++c)
      if (vis[c].hit_fraction >= ClassifierViews::kMinHitFraction && vis[c].mean_depth_m >= ClassifierViews::kMinMeanDepthM) seen[c] = std::move(vis[c].surface_ids);
    s.out.selection = SelectViewsBySetCover(seen, surface.size(), s.options.selection);
    if (s.options.view_selection == ClassifyViewSelection::kCover) {
      std::vector<Pose> chosen;
      for (int c : s.out.selection.chosen) chosen.push_back(poses[size_t(c)]);
      poses = std::move(chosen);
      to_hook.assign(poses.size(), 1);
    } else {
      to_hook.assign(poses.size(), 0);
      for (int c : s.out.selection.chosen) to_hook[size_t(c)] = 1;
    }
    s.out.seconds_selection = Seconds(ts);
    SEMVOX_INFO("view selection: " << s.out.selection.chosen.size() << " of " << s.out.selection.candidates << " candidate views cover "
                                   << 100.0 * s.out.selection.coverage() << "% of " << s.out.selection.surface_voxels << " surface voxels "
                                   << s.options.selection.min_views_per_voxel << " times (candidates: "
                                   << 100.0 * s.out.selection.coverable() << "%), " << s.out.seconds_selection << " s");
  }
  const int K = s.models->level.num_classes();
  const std::vector<bool> object_classes = RoomObjectClasses(s.models->level.class_names);
  constexpr size_t kBatch = 8;
  struct Slot {
    RenderedView view;
    bool use = false;
    Superpixels superpixels;
    std::vector<float> probabilities;
    std::array<double, 12> room{};
    std::function<Status()> finish_hook;  // The view hook's serial part.
    int64_t pixels = 0, unfamiliar_pixels = 0;  // SemanticEvidence::view_pixels, unfamiliar_view_pixels.
    double room_unfamiliarity = 0;  // Of the room-type descriptor (NaN: not measured).
    double room_weight = 1;         // 1 - DiscountUnfamiliarRoomView's mix.
    Status status = Status::Ok();
  };
  std::vector<Slot> slots(kBatch);
  for (size_t b0 = 0; b0 < poses.size(); b0 += kBatch) {
    const size_t nb = std::min(kBatch, poses.size() - b0);
    tbb::parallel_for(size_t(0), nb, [&](size_t k) {
      Slot& slot = slots[k];
      slot.use = false;
      slot.finish_hook = nullptr;
      slot.pixels = slot.unfamiliar_pixels = 0;
      slot.room_unfamiliarity = std::numeric_limits<double>::quiet_NaN();
      slot.room_weight = 1;
      const Pose& pose = poses[b0 + k];
      slot.status = s.renderer->Render(camera, WorldFromCameraYawPitch(pose.p, pose.yaw, ClassifierViews::kPitchDeg), render, &slot.view);
      if (!slot.status.ok()) return;
      double depth_sum = 0;
      for (float d : slot.view.depth.data) depth_sum += d;
      const double hit_fraction = double(slot.view.hit_pixels) / double(slot.view.depth.data.size());
      if (hit_fraction < ClassifierViews::kMinHitFraction || (slot.view.hit_pixels && depth_sum / double(slot.view.hit_pixels) < ClassifierViews::kMinMeanDepthM)) return;
      Image<int32_t> predicted;
      std::optional<ViewClassification> classified;  // The built-in classifier's result (the hook may share it).
      if (s.onnx && s.onnx->object) {
        Result<ImageF32> q = s.onnx->object->PixelProbabilities(slot.view);
        if (!q.ok()) {
          slot.status = q.status();
          return;
        }
        slot.superpixels = Superpixels{};
        slot.probabilities = std::move(q->data);
        ImageF32 view_q;
        view_q.width = slot.view.camera.width, view_q.height = slot.view.camera.height, view_q.channels = K;
        view_q.data = slot.probabilities;
        predicted = PixelArgmax(view_q);
      } else {
        Result<ViewClassification> c = s.models->classifier->Classify(slot.view);
        if (!c.ok()) {
          slot.status = c.status();
          return;
        }
        classified = std::move(c).value();
        for (size_t sp = 0; sp < classified->unfamiliarity.size(); ++sp) {
          const int px = classified->observations.superpixels[sp].pixel_count;
          slot.pixels += px;
          if (classified->unfamiliarity[sp] > 1.f) slot.unfamiliar_pixels += px;
        }
        slot.probabilities.assign(classified->union_marginals.p.begin(), classified->union_marginals.p.end());
        predicted = PixelLabels(classified->superpixels, classified->union_labels);
      }
      std::vector<double> p;
      if (s.onnx && s.onnx->scene) {
        Result<std::vector<double>> r = s.onnx->scene->RoomTypeProbabilities(slot.view);
        if (!r.ok()) {
          slot.status = r.status();
          return;
        }
        p = std::move(r).value();
      } else {
        p = RoomTypeProbabilities(*s.models->room_knn, RoomViewDescriptor(slot.view, predicted, K),
                                  ObjectPixelFraction(slot.view, predicted, object_classes), kRoomMinObjectFraction,
                                  s.models->room_familiar_distance, &slot.room_unfamiliarity);
        if (s.options.room_view_familiarity && std::isfinite(slot.room_unfamiliarity))
          slot.room_weight = 1.0 - DiscountUnfamiliarRoomView(slot.room_unfamiliarity, &p);
      }
      for (size_t t = 0; t < 12 && t < p.size(); ++t) slot.room[t] = p[t];
      if (s.hook && to_hook[b0 + k]) {
        Result<std::function<Status()>> h = s.hook(slot.view, classified ? &*classified : nullptr);
        if (!h.ok()) {
          slot.status = h.status();
          return;
        }
        slot.finish_hook = std::move(h).value();
      }
      if (classified) slot.superpixels = std::move(classified->superpixels);
      slot.use = true;
    });
    for (size_t k = 0; k < nb; ++k) {
      Slot& slot = slots[k];
      SEMVOX_RETURN_IF_ERROR(slot.status);
      if (!slot.use) {
        ++s.out.skipped_views;
        continue;
      }
      s.acc->AddClassifiedView(slot.view, slot.superpixels.count > 0 ? &slot.superpixels.label : nullptr, slot.probabilities);
      s.out.view_pixels += slot.pixels;
      s.out.unfamiliar_view_pixels += slot.unfamiliar_pixels;
      if (std::isfinite(slot.room_unfamiliarity)) {
        ++s.out.room_views_measured;
        s.out.room_views_unfamiliar += slot.room_unfamiliarity > 1.0;
        s.out.room_view_weight_sum += slot.room_weight;
      }
      if (slot.finish_hook) {
        SEMVOX_RETURN_IF_ERROR(slot.finish_hook());
        ++s.out.hooked_views;
      }
      ViewRoomEvidence r;
      r.position = poses[b0 + k].p;
      r.yaw_rad = poses[b0 + k].yaw * M_PI / 180.0;
      r.hfov_rad = ClassifierViews::kHorizontalFovDeg * M_PI / 180.0;
      r.max_range_m = kRoomViewRangeM;
      r.p = slot.room;
      s.out.rooms.push_back(r);
      ++s.out.classification_views;
    }
  }
  s.out.seconds_classify = Seconds(t0);
  // Views that look unlike the training views get per-view labels the classifier cannot vouch for: say so
  // (docs/perception.md, "Unfamiliar appearance"). Generated scans: 0.02-0.04 flat, 0.22-0.25 randomised.
  constexpr double kWarnUnfamiliarViewShare = 0.35;
  if (s.out.view_pixels > 0 && double(s.out.unfamiliar_view_pixels) > kWarnUnfamiliarViewShare * double(s.out.view_pixels)) {
    const int percent = int(std::lround(100.0 * double(s.out.unfamiliar_view_pixels) / double(s.out.view_pixels)));
    SEMVOX_WARN("views: " << percent << " % of the classified pixels look unlike every training view, so the per-view labels there are "
                          "guesses (summary.json semantic.view_appearance; docs/perception.md, \"Unfamiliar appearance\")");
  }
  SEMVOX_INFO("classified " << s.out.classification_views << " views (" << s.out.skipped_views << " skipped: too close or too empty) in "
                            << s.out.seconds_classify << " s");
  return Status::Ok();
}

SemanticEvidence SemanticEvidenceBuilder::Finish() && {
  Impl& s = *impl_;
  s.out.voxels = std::move(*s.acc).Finish();
  s.acc.reset();
  if (!s.models->segments && !s.models->other && !s.models->items) return std::move(s.out);
  // Object segments of the map, classified by shape: their probabilities on the segments' CRF nodes.
  const auto t0 = Clock::now();
  auto segmentation = std::make_shared<SegmentationResult>(
      SegmentObjects(s.map->grid, s.map->floor_z, s.map->ceiling_z, s.map->ceiling_found, SegmentOptions{}));
  s.out.segmentation = segmentation;
  if (!s.models->segments) return std::move(s.out);
  const SegmentationResult& seg = *segmentation;
  const int K = s.models->level.num_classes();
  s.out.voxels.segment.assign(s.out.nodes.size() * size_t(K), 0.f);
  std::vector<std::vector<double>> p(seg.segments.size());
  std::vector<double> unfamiliarity(seg.segments.size());
  tbb::parallel_for(size_t(0), seg.segments.size(), [&](size_t i) {
    p[i] = s.models->segments->Probabilities({seg.segments[i].features.data(), seg.segments[i].features.size()}, &unfamiliarity[i]);
  });
  // A counter is a work surface at counter height: lower segments' counter probability goes to table.
  const int counter = s.models->level.class_of_nyu40[size_t(nyu40::kCounter)];
  const int table = s.models->level.class_of_nyu40[size_t(nyu40::kTable)];
  for (size_t i = 0; i < seg.segments.size(); ++i)
    if (LowCounterToTable(seg.segments[i].features[kSegTopSurface], counter, table, s.options.counter_min_top_m, &p[i]))
      ++s.out.low_counter_segments, s.out.low_counter_voxels += int64_t(seg.segments[i].voxels.size());
  s.out.familiar_distance = s.models->segments->familiar_distance();
  const bool knows_familiarity = std::isfinite(s.out.familiar_distance);
  if (knows_familiarity) s.out.unfamiliar_segment_voxels = 0, s.out.unfamiliar_segments = 0;
  for (size_t i = 0; i < seg.segments.size(); ++i) {
    s.out.segment_voxels += int64_t(seg.segments[i].voxels.size());
    if (knows_familiarity && unfamiliarity[i] > 1.0)
      s.out.unfamiliar_segment_voxels += int64_t(seg.segments[i].voxels.size()), ++s.out.unfamiliar_segments;
  }
  for (size_t i = 0; i < seg.segments.size(); ++i)
    for (uint32_t v : seg.segments[i].voxels) {
      const int32_t node = s.out.nodes.node_of_voxel[v];
      if (node < 0) continue;
      for (int k = 0; k < K; ++k) s.out.voxels.segment[size_t(node) * K + size_t(k)] = float(p[i][size_t(k)]);
    }
  s.out.num_segments = int(seg.segments.size());
  s.out.seconds_segments = Seconds(t0);
  SEMVOX_INFO("object segments: " << s.out.num_segments << " classified by shape in " << s.out.seconds_segments << " s");
  // A scan whose objects are shaped unlike the training scenes' gets labels the segment term cannot vouch for:
  // say so (docs/objects.md, "Unfamiliar segments"). Generated scans stay under 5 % (the warning's share is 30 %).
  constexpr double kWarnUnfamiliarShare = 0.3;
  if (knows_familiarity && s.out.segment_voxels > 0 &&
      double(s.out.unfamiliar_segment_voxels) > kWarnUnfamiliarShare * double(s.out.segment_voxels)) {
    const int percent = int(std::lround(100.0 * double(s.out.unfamiliar_segment_voxels) / double(s.out.segment_voxels)));
    SEMVOX_WARN("object segments: " << percent << " % of their voxels (" << s.out.unfamiliar_segments << " of " << s.out.num_segments
                                    << " segments) are shaped unlike every training segment, so their classes are guesses "
                                       "(summary.json semantic.object_segment_shapes; docs/objects.md, \"Unfamiliar segments\")");
  }
  return std::move(s.out);
}

}  // namespace semvox

