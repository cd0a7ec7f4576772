#include "apps/semantic_stage.h"

#include "apps/onnx_stage.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "core/file_util.h"
#include "core/labels.h"
#include "core/log.h"
#include "io/image_io.h"
#include "mapping/octomap_io.h"
#include "objects/object_segments.h"
#include "perception/room_evidence.h"
#include "perception/training_data.h"
#include "perception/view_classifier.h"

namespace semvox {
namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }
}  // namespace

const char* ClassifyViewSelectionName(ClassifyViewSelection s) {
  return s == ClassifyViewSelection::kAll                  ? "all"
         : s == ClassifyViewSelection::kCover              ? "cover"
         : s == ClassifyViewSelection::kAllObjectsOnCover ? "all_objects_on_cover"
                                                           : "auto";
}

ClassifyViewSelection ResolveViewSelection(ClassifyViewSelection s, const Scene&) {
  return s == ClassifyViewSelection::kAuto ? ClassifyViewSelection::kCover : s;
}

const char* VoxelCrfModelChoiceName(VoxelCrfModelChoice c) {
  return c == VoxelCrfModelChoice::kMesh ? "mesh" : c == VoxelCrfModelChoice::kCloud ? "cloud" : "auto";
}

bool ParseVoxelCrfModelChoice(const std::string& name, VoxelCrfModelChoice* c) {
  if (name == "mesh") *c = VoxelCrfModelChoice::kMesh;
  else if (name == "cloud") *c = VoxelCrfModelChoice::kCloud;
  else if (name == "auto") *c = VoxelCrfModelChoice::kAuto;
  else return false;
  return true;
}

bool FlatColouredMesh(const Mesh& mesh) {
  if (mesh.faces.empty() || !mesh.has_vertex_colors() || mesh.has_texture()) return false;
  size_t flat = 0;
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Rgb8 a = mesh.vertex_colors[size_t(f[0])], b = mesh.vertex_colors[size_t(f[1])], c = mesh.vertex_colors[size_t(f[2])];
    flat += a.r == b.r && a.g == b.g && a.b == b.b && a.r == c.r && a.g == c.g && a.b == c.b;
  }
  return 2 * flat >= mesh.faces.size();
}

bool ParseClassifyViewSelection(const std::string& name, ClassifyViewSelection* s) {
  if (name == "all") *s = ClassifyViewSelection::kAll;
  else if (name == "cover") *s = ClassifyViewSelection::kCover;
  else if (name == "all_objects_on_cover") *s = ClassifyViewSelection::kAllObjectsOnCover;
  else if (name == "auto") *s = ClassifyViewSelection::kAuto;
  else return false;
  return true;
}

bool SemanticStageOptions::Check(std::string* error) const {
  if (!CheckOptions(*this, Options(), error)) return false;
  if (std::abs(360.0 / classify_yaw_step_deg - std::round(360.0 / classify_yaw_step_deg)) > 1e-9) {
    if (error) *error = "classify_yaw_step_deg = " + std::to_string(classify_yaw_step_deg) + ". Violated constraint: divides 360";
    return false;
  }
  return selection.Check(error) && evidence.Check(error) && crf.Check(error);
}

std::vector<int> Nyu40OfClasses(const LabelLevel& level) {
  std::vector<int> nyu40;
  for (const std::string& name : level.class_names) nyu40.push_back(name == "other" ? nyu40::kOtherProp : Nyu40IdByName(name));
  return nyu40;
}

struct SemanticStage::Impl {
  const VoxelMap* map = nullptr;
  const ViewRenderer* renderer = nullptr;
  SemanticStageOptions options;
  LabelLevel level;
  std::unique_ptr<ViewClassifier> classifier;
  std::unique_ptr<KnnClassifier> room_knn;
  std::unique_ptr<KnnClassifier> segment_knn;  // Object segments by shape (absent: no segment term).
  int num_segments = 0;
  double seconds_segments = 0;
  VoxelCrfModel model;
  bool model_trained = false;
  std::string model_file;  // File name of the loaded Voxel-CRF model (voxel_crf.txt or voxel_crf_cloud.txt).
  VoxelCrfNodes nodes;
  std::unique_ptr<EvidenceAccumulator> acc;
  VoxelEvidence evidence;
  VoxelCrfResult result;
  SemanticMap semantic;
  VoxelGrid refined;
  std::vector<ClassifiedViewRoomEvidence> rooms;
  int classification_views = 0, skipped_views = 0;
  ViewSelection selection;  // Candidates and cover (kCover), or candidates only (kAll).
  double seconds_selection = 0;
  double seconds_classify = 0, seconds_depth = 0, seconds_solve = 0;
  int hooked_views = 0;  // Classified views the view hook saw.
  const OnnxModels* onnx = nullptr;
  ViewHook hook;
};

SemanticStage::SemanticStage(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SemanticStage::~SemanticStage() = default;
void SemanticStage::SetOnnxModels(const OnnxModels* models) { impl_->onnx = models; }
void SemanticStage::SetViewHook(ViewHook hook) { impl_->hook = std::move(hook); }

Result<std::unique_ptr<SemanticStage>> SemanticStage::Create(const VoxelMap& map, const ViewRenderer& renderer,
                                                             const SemanticStageOptions& options, const std::string& models_dir) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("configuration: semantic." + error);
  auto impl = std::make_unique<Impl>();
  impl->map = &map;
  impl->renderer = &renderer;
  impl->options = options;
  impl->level = SecondLevel();
  Result<ViewClassifier> clf = ViewClassifier::Load(models_dir + "/second", ViewClassifierOptions{});
  if (!clf.ok())
    return Status::InvalidInput(FileError(models_dir + "/second.*", "cannot load the per-view classifier: " + clf.status().message(),
                                          "pass --models DIR or run `semvox train`"));
  impl->classifier = std::make_unique<ViewClassifier>(std::move(clf).value());
  Result<KnnClassifier> room = KnnClassifier::Load(models_dir + "/room_type_knn.bin");
  if (!room.ok()) return room.status();
  impl->room_knn = std::make_unique<KnnClassifier>(std::move(room).value());
  std::error_code ec;
  if (const std::string segment_path = models_dir + "/object_segments.knn"; fs::exists(segment_path, ec)) {
    Result<KnnClassifier> seg = KnnClassifier::Load(segment_path);
    if (!seg.ok()) return seg.status();
    if (seg->dims() != kNumSegmentFeatures || seg->num_classes() != impl->level.num_classes())
      return Status::InvalidInput(FileError(segment_path, "not an object-segment model for the second-level classes", "re-run `semvox train`"));
    impl->segment_knn = std::make_unique<KnnClassifier>(std::move(seg).value());
  } else {
    SEMVOX_WARN(segment_path << ": not found; the Voxel-CRF runs without the object-segment term (run `semvox train`)");
  }
  std::string model_path = models_dir + "/voxel_crf.txt";
  if (options.crf_model == VoxelCrfModelChoice::kCloud) {
    const std::string cloud_path = models_dir + "/voxel_crf_cloud.txt";
    if (fs::exists(cloud_path, ec)) model_path = cloud_path;
    else SEMVOX_WARN(cloud_path << ": not found; the Voxel-CRF uses " << model_path << " (run `semvox train --voxel-crf --voxel-crf-style cloud`)");
  }
  if (fs::exists(model_path, ec)) {
    Result<VoxelCrfModel> m = VoxelCrfModel::Load(model_path);
    if (!m.ok()) return m.status();
    impl->model = std::move(m).value();
    impl->model_trained = true;
    impl->model_file = fs::path(model_path).filename().string();
  } else {
    impl->model = VoxelCrfModel::Default(Nyu40OfClasses(impl->level), impl->level.class_names);
    SEMVOX_WARN(model_path << ": not found; the Voxel-CRF uses untrained default weights (run `semvox train`)");
  }
  if (impl->model.num_classes() != impl->level.num_classes())
    return Status::InvalidInput(FileError(model_path, "class count differs from the per-view classifier's", "re-run `semvox train`"));
  impl->nodes = SelectVoxelCrfNodes(map.grid, map.floor_z, map.ceiling_z, options.evidence);
  MarkPointNodes(map.point_voxels, &impl->nodes);
  impl->acc = std::make_unique<EvidenceAccumulator>(map.grid, impl->nodes, impl->level.num_classes(), options.evidence);
  SEMVOX_INFO("voxel CRF: " << impl->nodes.size() << " nodes (" << impl->nodes.count_state(VoxelState::kOccupied) << " occupied, "
                            << impl->nodes.count_state(VoxelState::kFree) << " free, " << impl->nodes.count_state(VoxelState::kUnknown)
                            << " unknown)");
  return std::unique_ptr<SemanticStage>(new SemanticStage(std::move(impl)));
}

ViewSink SemanticStage::DepthSink() {
  return [this](const ViewRecord& record, const RenderedView& view) {
    if (!record.kept()) return Status::Ok();
    const auto t0 = Clock::now();
    impl_->acc->AddDepthView(view);
    impl_->seconds_depth += Seconds(t0);
    return Status::Ok();
  };
}

Status SemanticStage::ClassifyViews(const std::vector<Eigen::Vector3d>& positions) {
  Impl& s = *impl_;
  const auto t0 = Clock::now();
  const TrainingViewsOptions tv;
  const PinholeCamera camera = PinholeCamera::FromHorizontalFov(s.options.classify_width, s.options.classify_height, tv.horizontal_fov_deg);
  double z = s.map->floor_z + tv.eye_height_m;
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
  s.selection = ViewSelection{};
  s.selection.candidates = poses.size();
  // Per candidate: whether the view hook sees it (every classified view, or only the cover's).
  std::vector<char> to_hook(poses.size(), 1);
  const bool cover = s.options.view_selection == ClassifyViewSelection::kCover ||
                     s.options.view_selection == ClassifyViewSelection::kAllObjectsOnCover;
  if (cover && !poses.empty()) {
    // The views that add evidence: candidates the classifier would skip are left out of the cover.
    const auto ts = Clock::now();
    std::vector<Eigen::Isometry3d> world_from_camera;
    for (const Pose& pose : poses) world_from_camera.push_back(WorldFromCameraYawPitch(pose.p, pose.yaw, tv.pitch_deg));
    const std::vector<uint32_t> surface = SurfaceVoxels(s.map->grid);
    std::vector<CandidateVisibility> vis =
        MeasureCandidateVisibility(*s.renderer, s.map->grid, surface, camera, world_from_camera, render, s.options.selection);
    std::vector<std::vector<uint32_t>> seen(vis.size());
    for (size_t c = 0; c < vis.size(); ++c)
      if (vis[c].hit_fraction >= tv.min_hit_fraction && vis[c].mean_depth_m >= tv.min_mean_depth_m) seen[c] = std::move(vis[c].surface_ids);
    s.selection = SelectViewsBySetCover(seen, surface.size(), s.options.selection);
    if (s.options.view_selection == ClassifyViewSelection::kCover) {
      std::vector<Pose> chosen;
      for (int c : s.selection.chosen) chosen.push_back(poses[size_t(c)]);
      poses = std::move(chosen);
      to_hook.assign(poses.size(), 1);
    } else {
      to_hook.assign(poses.size(), 0);
      for (int c : s.selection.chosen) to_hook[size_t(c)] = 1;
    }
    s.seconds_selection = Seconds(ts);
    SEMVOX_INFO("view selection: " << s.selection.chosen.size() << " of " << s.selection.candidates << " candidate views cover "
                                   << 100.0 * s.selection.coverage() << "% of " << s.selection.surface_voxels << " surface voxels "
                                   << s.options.selection.min_views_per_voxel << " times (candidates: "
                                   << 100.0 * s.selection.coverable() << "%), " << s.seconds_selection << " s");
  }
  const int K = s.level.num_classes();
  const std::vector<bool> object_classes = RoomObjectClasses(s.level.class_names);
  constexpr size_t kBatch = 8;
  struct Slot {
    RenderedView view;
    bool use = false;
    Superpixels superpixels;
    std::vector<float> probabilities;
    std::array<double, 12> room{};
    std::function<Status()> finish_hook;  // The view hook's serial part.
    Status status = Status::Ok();
  };
  std::vector<Slot> slots(kBatch);
  for (size_t b0 = 0; b0 < poses.size(); b0 += kBatch) {
    const size_t nb = std::min(kBatch, poses.size() - b0);
    tbb::parallel_for(size_t(0), nb, [&](size_t k) {
      Slot& slot = slots[k];
      slot.use = false;
      slot.finish_hook = nullptr;
      const Pose& pose = poses[b0 + k];
      slot.status = s.renderer->Render(camera, WorldFromCameraYawPitch(pose.p, pose.yaw, tv.pitch_deg), render, &slot.view);
      if (!slot.status.ok()) return;
      double depth_sum = 0;
      for (float d : slot.view.depth.data) depth_sum += d;
      const double hit_fraction = double(slot.view.hit_pixels) / double(slot.view.depth.data.size());
      if (hit_fraction < tv.min_hit_fraction || (slot.view.hit_pixels && depth_sum / double(slot.view.hit_pixels) < tv.min_mean_depth_m)) return;
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
        Result<ViewClassification> c = s.classifier->Classify(slot.view);
        if (!c.ok()) {
          slot.status = c.status();
          return;
        }
        classified = std::move(c).value();
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
        p = RoomTypeProbabilities(*s.room_knn, RoomViewDescriptor(slot.view, predicted, K),
                                  ObjectPixelFraction(slot.view, predicted, object_classes), kRoomMinObjectFraction);
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
        ++s.skipped_views;
        continue;
      }
      s.acc->AddClassifiedView(slot.view, slot.superpixels.count > 0 ? &slot.superpixels.label : nullptr, slot.probabilities);
      if (slot.finish_hook) {
        SEMVOX_RETURN_IF_ERROR(slot.finish_hook());
        ++s.hooked_views;
      }
      ClassifiedViewRoomEvidence r;
      r.position = poses[b0 + k].p;
      r.yaw_rad = poses[b0 + k].yaw * M_PI / 180.0;
      r.hfov_rad = tv.horizontal_fov_deg * M_PI / 180.0;
      r.max_range_m = kRoomViewRangeM;
      r.p = slot.room;
      s.rooms.push_back(r);
      ++s.classification_views;
    }
  }
  s.seconds_classify = Seconds(t0);
  SEMVOX_INFO("classified " << s.classification_views << " views (" << s.skipped_views << " skipped: too close or too empty) in "
                            << s.seconds_classify << " s");
  return Status::Ok();
}

Status SemanticStage::Solve() { return SolveWith(impl_->options.crf); }

const VoxelCrfResult& SemanticStage::crf_result() const { return impl_->result; }

Status SemanticStage::SolveWith(const VoxelCrfOptions& crf) {
  Impl& s = *impl_;
  const auto t0 = Clock::now();
  FinishEvidence();
  SEMVOX_RETURN_IF_ERROR(SolveVoxelCrf(s.map->grid, s.nodes, s.evidence, s.map->floor_z, s.map->ceiling_z, s.model, crf, &s.result));
  s.semantic = MakeSemanticMap(s.map->grid, s.nodes, s.evidence, s.result, s.model);
  s.refined = s.semantic.RefinedGrid(s.map->grid, s.nodes);
  s.seconds_solve = Seconds(t0);
  SEMVOX_INFO("voxel CRF: " << s.semantic.occupied.size() << " occupied voxels labelled (" << s.semantic.completed_count()
                            << " completed), " << s.result.num_planes << " planes, " << s.result.num_object_cliques
                            << " object cliques, " << s.result.iterations.size() << " iterations, " << s.seconds_solve << " s");
  return Status::Ok();
}

void SemanticStage::FinishEvidence() {
  Impl& s = *impl_;
  if (!s.acc) return;
  s.evidence = std::move(*s.acc).Finish();
  s.acc.reset();
  if (!s.segment_knn) return;
  // Object segments of the map, classified by shape: their probabilities on the segments' CRF nodes.
  const auto t0 = Clock::now();
  const SegmentationResult seg = SegmentObjects(s.map->grid, s.map->floor_z, s.map->ceiling_z, s.map->ceiling_found, SegmentOptions{});
  const int K = s.level.num_classes();
  s.evidence.segment.assign(s.nodes.size() * size_t(K), 0.f);
  std::vector<std::vector<double>> p(seg.segments.size());
  tbb::parallel_for(size_t(0), seg.segments.size(), [&](size_t i) {
    p[i] = s.segment_knn->Probabilities({seg.segments[i].features.data(), seg.segments[i].features.size()});
  });
  for (size_t i = 0; i < seg.segments.size(); ++i)
    for (uint32_t v : seg.segments[i].voxels) {
      const int32_t node = s.nodes.node_of_voxel[v];
      if (node < 0) continue;
      for (int k = 0; k < K; ++k) s.evidence.segment[size_t(node) * K + size_t(k)] = float(p[i][size_t(k)]);
    }
  s.num_segments = int(seg.segments.size());
  s.seconds_segments = Seconds(t0);
  SEMVOX_INFO("object segments: " << s.num_segments << " classified by shape in " << s.seconds_segments << " s");
}

const VoxelCrfNodes& SemanticStage::nodes() const { return impl_->nodes; }
const VoxelCrfModel& SemanticStage::model() const { return impl_->model; }

std::vector<int> SemanticStage::GroundTruthNodeLabels(const std::unordered_map<uint64_t, int>& nyu40_of_key) const {
  const Impl& s = *impl_;
  std::vector<int> gt(s.nodes.size(), 0);
  for (size_t i = 0; i < gt.size(); ++i) {
    const auto c = s.map->grid.Cell(s.nodes.voxel[i]);
    const auto it = nyu40_of_key.find(s.map->grid.KeyOf(c[0], c[1], c[2]).Pack());
    if (it == nyu40_of_key.end() || it->second <= 0 || it->second >= kNumNyu40) continue;
    const int cls = s.level.class_of_nyu40[size_t(it->second)];
    if (cls >= 0) gt[i] = cls + 1;
  }
  return gt;
}

void SemanticStage::AddLayoutCounts(const std::vector<int>& gt, std::vector<double>* counts) const {
  const Impl& s = *impl_;
  const int K = s.level.num_classes();
  counts->resize(size_t(LayoutPrior::kHeightBins) * LayoutPrior::kNormalBins * size_t(K), 0.0);
  for (size_t i = 0; i < gt.size(); ++i) {
    if (gt[i] <= 0) continue;
    const auto c = s.map->grid.Cell(s.nodes.voxel[i]);
    const int hb = LayoutPrior::HeightBin(s.map->grid.CellCenter(c[0], c[1], c[2]).z(), s.map->floor_z, s.map->ceiling_z);
    const int nb = LayoutPrior::NormalBin(s.evidence.normal[i]);
    (*counts)[(size_t(hb) * LayoutPrior::kNormalBins + size_t(nb)) * size_t(K) + size_t(gt[i] - 1)] += 1.0;
  }
}

VoxelCrfTrainingExample SemanticStage::TrainingExample(std::vector<int> gt, const VoxelCrfModel& model) const {
  const Impl& s = *impl_;
  VoxelCrfTrainingExample ex;
  const std::vector<DetectedPlane> planes = DetectPlanes(s.map->grid, s.nodes, s.evidence, s.options.crf.planes);
  const std::vector<int32_t> vis = ComputeVisibility(s.map->grid, s.nodes, s.evidence, gt);
  ex.problem = BuildVoxelCrfProblem(s.map->grid, s.nodes, s.evidence, s.map->floor_z, s.map->ceiling_z, model, planes, s.options.crf, vis);
  ex.gt = std::move(gt);
  return ex;
}

const VoxelGrid& SemanticStage::refined_grid() const { return impl_->refined; }
const SemanticMap& SemanticStage::semantic_map() const { return impl_->semantic; }
SemanticMap* SemanticStage::mutable_semantic_map() { return &impl_->semantic; }
const std::vector<ClassifiedViewRoomEvidence>& SemanticStage::room_evidence() const { return impl_->rooms; }

Status SemanticStage::Write(const std::string& outdir, const ImageU16* room_ids, double band_min_m, double band_max_m,
                            const ImageRgb8& occupancy_image, const Eigen::Isometry3d& input_from_world) {
  Impl& s = *impl_;
  const VoxelGrid& grid = s.map->grid;
  if (room_ids) AssignRooms(*room_ids, grid, &s.semantic);
  SEMVOX_RETURN_IF_ERROR(WriteVoxelsPly(s.semantic, (fs::path(outdir) / "voxels.ply").string(), input_from_world));
  // map.ot: every known voxel of the refined map; occupied ones with label and confidence.
  std::vector<SemanticVoxel> voxels;
  std::vector<int32_t> record(grid.size(), -1);
  for (size_t k = 0; k < s.semantic.occupied.size(); ++k) record[s.semantic.occupied[k].voxel] = int32_t(k);
  const auto& d = grid.dims();
  for (int iz = 0; iz < d[2]; ++iz)
    for (int iy = 0; iy < d[1]; ++iy)
      for (int ix = 0; ix < d[0]; ++ix) {
        const size_t i = grid.Index(ix, iy, iz);
        const VoxelState st = s.refined.state(i);
        if (st == VoxelState::kUnknown) continue;
        SemanticVoxel v;
        v.key = grid.KeyOf(ix, iy, iz);
        v.occupied = st == VoxelState::kOccupied;
        if (record[i] >= 0) v.label = s.semantic.occupied[size_t(record[i])].label, v.confidence = s.semantic.occupied[size_t(record[i])].confidence;
        voxels.push_back(v);
      }
  SEMVOX_RETURN_IF_ERROR(WriteSemanticOctree(voxels, grid.resolution(), (fs::path(outdir) / "map.ot").string()));
  const ImageU16 top = SemanticTopView(s.semantic, grid, s.map->floor_z, band_min_m, band_max_m);
  SEMVOX_RETURN_IF_ERROR(WriteImage((fs::path(outdir) / "semantic_topview_labels.png").string(), top));
  SEMVOX_RETURN_IF_ERROR(WriteImage((fs::path(outdir) / "semantic_topview.png").string(), ColourSemanticTopView(top, occupancy_image)));
  return Status::Ok();
}

nlohmann::ordered_json SemanticStage::Summary() const {
  const Impl& s = *impl_;
  nlohmann::ordered_json j;
  j["model"] = s.model_trained ? "models/" + s.model_file : std::string("untrained defaults");
  j["classification_views"] = s.classification_views;
  nlohmann::ordered_json sel = {{"method", ClassifyViewSelectionName(s.options.view_selection)},
                                 {"candidates", s.selection.candidates},
                                 {"width", s.options.classify_width},
                                 {"height", s.options.classify_height}};
  if (s.options.view_selection == ClassifyViewSelection::kCover || s.options.view_selection == ClassifyViewSelection::kAllObjectsOnCover) {
    const auto share = [&](size_t n) { return s.selection.surface_voxels ? double(n) / double(s.selection.surface_voxels) : 0.0; };
    sel["chosen"] = s.selection.chosen.size();
    sel["hooked_views"] = s.hooked_views;  // Classified views the support / clutter stage saw.
    sel["min_views_per_voxel"] = s.options.selection.min_views_per_voxel;
    sel["max_incidence_deg"] = s.options.selection.max_incidence_deg;
    sel["surface_voxels"] = s.selection.surface_voxels;
    sel["coverage"] = s.selection.coverage();            // Seen >= k times by the chosen views.
    sel["coverage_candidates"] = s.selection.coverable();  // ... by all candidates.
    sel["seen_once"] = share(s.selection.seen_voxels);
  }
  j["view_selection"] = sel;
  j["skipped_classification_views"] = s.skipped_views;
  const auto holding_points = std::count(s.nodes.holds_point.begin(), s.nodes.holds_point.end(), uint8_t(1));
  j["nodes"] = {{"total", s.nodes.size()},
                {"occupied", s.nodes.count_state(VoxelState::kOccupied)},
                {"free", s.nodes.count_state(VoxelState::kFree)},
                {"unknown", s.nodes.count_state(VoxelState::kUnknown)},
                {"holding_points", holding_points},
                {"kept_occupied", s.options.crf.keep_scan_points ? holding_points : 0}};
  j["rays"] = s.evidence.rays.size();
  j["planes"] = s.result.num_planes;
  j["object_cliques"] = s.result.num_object_cliques;
  nlohmann::ordered_json its = nlohmann::ordered_json::array();
  for (const auto& it : s.result.iterations)
    its.push_back({{"energy_initial", it.energy_initial}, {"energy_final", it.energy_final}, {"energy_per_sweep", it.energy_per_sweep},
                   {"sweeps", it.sweeps}, {"edges", it.edges}, {"cliques", it.cliques}, {"changed_labels", it.changed_labels},
                   {"changed_visibility", it.changed_visibility}, {"seconds", it.seconds},
                   {"phase_seconds", {{"build", it.seconds_build}, {"energy", it.seconds_energy}, {"alpha_expansion", it.seconds_expansion},
                                      {"max_flow", it.seconds_max_flow}, {"visibility", it.seconds_visibility}}}});
  j["iterations"] = its;
  j["object_segments"] = s.segment_knn ? nlohmann::ordered_json(s.num_segments) : nlohmann::ordered_json("no model");
  j["occupied_voxels"] = s.semantic.occupied.size();
  j["completed_voxels"] = s.semantic.completed_count();
  nlohmann::ordered_json hist = nlohmann::ordered_json::object();
  for (const auto& [label, count] : s.semantic.LabelCounts())
    hist[label > 0 && label < kNumNyu40 ? Nyu40Labels()[size_t(label)].name : std::to_string(label)] = count;
  j["labels"] = hist;
  j["seconds"] = {{"depth_evidence", s.seconds_depth}, {"view_selection", s.seconds_selection}, {"classify", s.seconds_classify}, {"crf", s.result.seconds},
                  {"crf_planes", s.result.seconds_planes}, {"crf_ray_starts", s.result.seconds_ray_starts},
                  {"crf_confidence", s.result.seconds_confidence}, {"object_segments", s.seconds_segments},
                  {"solve_total", s.seconds_solve}};
  j["files"] = {"voxels.ply", "map.ot", "semantic_topview.png", "semantic_topview_labels.png"};
  return j;
}

}  // namespace semvox
