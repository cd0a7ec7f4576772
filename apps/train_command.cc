// `semvox train`: trains the per-view classifiers on generated training apartments, scores
// them on the validation apartments and writes the model files and a report.
//
//   semvox train [-o models] [--train-seeds 0-39] [--val-seeds 100-109] [--max-rows 20000] [--crf-holdout 5]
//
// The k-NN models learn from the training seeds but the last `crf-holdout` ones; the CRF weights are then
// learned (negative log pseudo-likelihood) on those held-out seeds, whose k-NN unaries are not
// self-matches. Writes OUT/{nyu4,second}.{image_knn,full_knn}.bin, OUT/{nyu4,second}.crf_weights.txt and
// OUT/support_clutter.svm and OUT/object_proposals.svm, OUT/train_report.json
// (per level and method: pixel-wise global accuracy, average recall and per-class recall on the
// validation views). Deterministic: the same seeds give the same bytes.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <regex>

#include "apps/commands.h"
#include "core/file_util.h"
#include "core/labels.h"
#include "core/log.h"
#include "objects/proposal_training.h"
#include "objects/segment_training.h"
#include "objects/support_training.h"
#include "perception/crf_learning.h"
#include "perception/room_evidence.h"
#include "perception/training_data.h"
#include "perception/view_classifier.h"
#include "pipeline/voxel_crf_training.h"
#include "rooms/r2v_plan.h"
#include "rooms/room_type_training.h"

namespace semvox {

// Parses "A-B" or "A" or "A,B,C".
Status ParseSeedList(const std::string& text, const char* flag, std::vector<uint64_t>* seeds) {
  seeds->clear();
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    try {
      const size_t dash = item.find('-');
      size_t used = 0;
      if (dash == std::string::npos) {
        seeds->push_back(std::stoull(item, &used));
        if (used != item.size()) throw std::invalid_argument(item);
      } else {
        const uint64_t a = std::stoull(item.substr(0, dash)), b = std::stoull(item.substr(dash + 1));
        if (b < a || b - a > 100000) throw std::invalid_argument(item);
        for (uint64_t s = a; s <= b; ++s) seeds->push_back(s);
      }
    } catch (const std::exception&) {
      return Status::InvalidInput(std::string(flag) + " = '" + text + "': expected seeds like 0-39 or 1,5,9");
    }
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  return seeds->empty() ? Status::InvalidInput(std::string(flag) + " is empty") : Status::Ok();
}

namespace {

// The real R2V floor plans: --r2v-dir, else ../shared/data/r2v relative to the working directory (`semvox train`
// runs from the source tree's root, as its default output `models` says).
std::string R2vDirectory(const TrainArgs& args) { return args.r2v_dir.empty() ? "../shared/data/r2v" : args.r2v_dir; }

// Keeps at most `max_rows` rows of each model's training set, at an even stride (deterministic).
void Subsample(int max_rows, TrainingSet* set) {
  auto thin = [&](std::vector<float>* f, std::vector<int>* l, int dims) {
    if (max_rows <= 0 || l->size() <= size_t(max_rows)) return;
    std::vector<float> nf;
    std::vector<int> nl;
    const double stride = double(l->size()) / max_rows;
    for (int r = 0; r < max_rows; ++r) {
      const size_t i = size_t(r * stride);
      nl.push_back((*l)[i]);
      nf.insert(nf.end(), f->begin() + long(i * size_t(dims)), f->begin() + long((i + 1) * size_t(dims)));
    }
    f->swap(nf);
    l->swap(nl);
  };
  thin(&set->image_features, &set->image_labels, kImageObservationDims);
  thin(&set->full_features, &set->full_labels, kObservationDims);
}

nlohmann::json Scores(const ConfusionMatrix& cm, const LabelLevel& level) {
  auto num = [](double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(std::round(v * 1e4) / 1e4); };
  nlohmann::json j;
  j["global_accuracy"] = num(cm.GlobalAccuracy());
  j["average_recall"] = num(cm.AverageRecall());
  j["pixels"] = cm.Total();
  for (int c = 0; c < level.num_classes(); ++c) j["recall"][level.class_names[size_t(c)]] = num(cm.Recall(c));
  return j;
}

using SegmentedViewFn = std::function<Status(const LabelledView&, const Superpixels&, const ViewObservations&)>;

// A view cut into superpixels with their observations once (both label levels and the room-type evidence
// share the segmentation).
Status SegmentView(const LabelledView& v, const ViewClassifierOptions& options, const SegmentedViewFn& fn) {
  Result<Superpixels> sp = ComputeSuperpixels(v.view->rgb, options.superpixels);
  if (!sp.ok()) return sp.status();
  Result<ViewObservations> obs = ComputeObservations(*v.view, *sp, options.observations);
  if (!obs.ok()) return obs.status();
  return fn(v, *sp, *obs);
}

// Every kept view of apartment `seed`, segmented (SegmentView).
Status ForEachSegmentedView(uint64_t seed, const TrainingViewsOptions& views, const ViewClassifierOptions& options,
                            const SegmentedViewFn& fn) {
  return ForEachApartmentView(seed, views, [&](const LabelledView& v) { return SegmentView(v, options, fn); });
}

// The object-segment classifier on randomised scans of --segment-seeds, scored on val_seeds; writes
// OUT/object_segments.knn (or .forest, --segment-classifier), and the "other" and item labellers
// OUT/other_labels.knn and OUT/item_labels.knn from the same scans, and returns the report's JSON.
Result<nlohmann::json> TrainSegments(const TrainArgs& args, const std::vector<uint64_t>& val_seeds, const LabelLevel& level) {
  SegmentTrainingOptions so;
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.segment_seeds, "--segment-seeds", &so.train_seeds));
  so.val_seeds = val_seeds;
  so.scans.style = TrainingStyle::kRandomised;  // Segments always learn from randomised scans (cloud spacing, holes).
  if (!ParseSegmentClassifierKind(args.segment_classifier, &so.classifier))
    return Status::InvalidInput("--segment-classifier: expected knn or forest, got '" + args.segment_classifier + "'");
  SegmentTrainingSummary summary;
  std::optional<OtherLabeller> other;
  std::optional<ItemLabeller> items;
  Result<SegmentClassifier> seg = TrainSegmentClassifier(so, &summary, &other, &items);
  if (!seg.ok()) return seg.status();
  SEMVOX_RETURN_IF_ERROR(seg->SaveToDirectory(args.outdir));
  SEMVOX_RETURN_IF_ERROR(other->Save(args.outdir + "/" + kOtherLabellerFile));
  SEMVOX_RETURN_IF_ERROR(items->Save(args.outdir + "/" + kItemLabellerFile));
  nlohmann::json j;
  j["seeds"] = args.segment_seeds;
  j["classifier"] = SegmentClassifierKindName(so.classifier);
  j["train_segments"] = summary.train_segments;
  j["val_segments"] = summary.val_segments;
  j["val_segment_accuracy"] = std::round(1e4 * summary.val_segment_accuracy) / 1e4;
  j["val_voxels"] = Scores(summary.val_voxels, level);
  // The fine labels of "other" (other_labels.knn), scored on the validation segments' "other" voxels.
  nlohmann::json o;
  o["train_rows"] = summary.other_train_rows;
  o["val_rows"] = summary.other_val_rows;
  o["val_voxels"] = {{"global_accuracy", std::round(1e4 * summary.other_val_voxels.GlobalAccuracy()) / 1e4},
                     {"average_recall", std::round(1e4 * summary.other_val_voxels.AverageRecall()) / 1e4}};
  for (int id = 1; id < kNumNyu40; ++id) {
    const double r = summary.other_val_voxels.Recall(id);
    if (!std::isnan(r)) o["val_voxels"]["recall"][Nyu40Labels()[size_t(id)].name] = std::round(1e4 * r) / 1e4;
  }
  j["other_labels"] = o;
  // The items on top (item_labels.knn): class 0 is "part of the furniture".
  nlohmann::json it;
  it["train_rows"] = summary.item_train_rows;
  it["val_rows"] = summary.item_val_rows;
  it["val_voxels_right"] = std::round(1e4 * summary.item_val_voxels.GlobalAccuracy()) / 1e4;
  for (int id = 0; id < kNumNyu40; ++id) {
    const double r = summary.item_val_voxels.Recall(id);
    if (!std::isnan(r)) it["val_recall"][id == 0 ? "part of the furniture" : Nyu40Labels()[size_t(id)].name] = std::round(1e4 * r) / 1e4;
  }
  j["item_labels"] = it;
  std::printf("%s", summary.ToText(level).c_str());
  return j;
}

}  // namespace

Status RunTrainRoomShapes(const TrainArgs& args) {
  const std::string dir = R2vDirectory(args);
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Status::InvalidInput(FileError(dir, "no such directory (the R2V plans)", "pass --r2v-dir DIR, or run from the source tree's root"));
  std::filesystem::create_directories(args.outdir, ec);
  if (ec) return Status::InvalidInput(FileError(args.outdir, "cannot create the output directory", ec.message()));
  std::vector<int> features;
  for (size_t start = 0; start <= args.room_shape_features.size() && !args.room_shape_features.empty();) {
    size_t end = args.room_shape_features.find(',', start);
    if (end == std::string::npos) end = args.room_shape_features.size();
    const std::string name = args.room_shape_features.substr(start, end - start);
    const int f = RoomShapeFeatureIndex(name);
    if (f < 0) return Status::InvalidInput("--room-shape-features: unknown feature '" + name + "' (hint: `semvox train --help` lists them)");
    features.push_back(f);
    start = end + 1;
  }
  if (features.empty())
    for (int f = 0; f < kRoomShapeFeatures; ++f) features.push_back(f);
  RoomShapeTrainingReport r;
  Result<RoomShapeModel> model = TrainRoomShapesFromR2v(dir, kR2vTrainingPlans, &r, features);
  if (!model.ok()) return model.status();
  SEMVOX_RETURN_IF_ERROR(SaveRoomShapeModel(*model, args.outdir + "/room_shape.json"));
  std::printf("%s", r.ToText().c_str());
  nlohmann::json j;
  j["provenance"] = model->provenance;
  j["train_plans"] = r.train_plans, j["val_plans"] = r.val_plans, j["skipped_plans"] = r.skipped_plans;
  j["train_rooms"] = r.train_rooms, j["val_rooms"] = r.val_rooms;
  j["val_room_accuracy"] = std::round(1e4 * r.val_room_accuracy) / 1e4;
  j["val_area_accuracy"] = std::round(1e4 * r.val_area_accuracy) / 1e4;
  j["val_class_average"] = std::round(1e4 * r.val_class_average) / 1e4;
  j["val_confusion_m2"] = r.confusion_m2;
  j["features"] = nlohmann::json::array();
  for (const int f : model->features) j["features"].push_back(RoomShapeFeatureNames()[size_t(f)]);
  for (size_t i = 0; i < r.adjacency_weights.size() && i < r.adjacency_area_accuracy.size(); ++i)
    j["val_with_adjacency"].push_back({{"weight", r.adjacency_weights[i]},
                                       {"area_accuracy", std::round(1e4 * r.adjacency_area_accuracy[i]) / 1e4},
                                       {"class_average", std::round(1e4 * r.adjacency_class_average[i]) / 1e4}});
  return WriteFileAtomic(args.outdir + "/room_shape_report.json", j.dump(2) + "\n");
}

Status RunTrainRoomTypeStatistics(const TrainArgs& args) {
  const std::string dir = R2vDirectory(args);
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Status::InvalidInput(FileError(dir, "no such directory (the R2V plans)", "pass --r2v-dir DIR, or run from the source tree's root"));
  std::vector<uint64_t> seeds;
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.train_seeds, "--train-seeds", &seeds));
  const std::string path = args.outdir + "/room_type_crf.json";
  Result<RoomTypeModel> model = LoadRoomTypeModel(path);
  if (!model.ok()) return model.status();
  int plans = 0;
  SEMVOX_RETURN_IF_ERROR(RefreshR2vFixtureStatistics(seeds, dir, kR2vTrainingPlans, &*model, &plans));
  // The provenance names the plans the statistics now come from.
  std::string& prov = model->provenance;
  static const std::regex kR2vCount(R"(\+ [0-9]+ R2V plans( [0-9]+-[0-9]+)? \(fixtures\))");
  const std::string now = "+ " + std::to_string(plans) + " R2V plans 0-" + std::to_string(kR2vTrainingPlans - 1) + " (fixtures)";
  prov = std::regex_search(prov, kR2vCount) ? std::regex_replace(prov, kR2vCount, now) : prov + "; fixture statistics " + now;
  SEMVOX_RETURN_IF_ERROR(SaveRoomTypeModel(*model, path));
  std::printf("%s: R2V fixture statistics from %zu generated apartments and %d R2V plans (of the first %d)\n", path.c_str(), seeds.size(),
              plans, kR2vTrainingPlans);
  return Status::Ok();
}

Status RunTrainRoomTypeEvidence(const TrainArgs& args) {
  const std::string dir = R2vDirectory(args);
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Status::InvalidInput(FileError(dir, "no such directory (the R2V plans)", "pass --r2v-dir DIR, or run from the source tree's root"));
  const std::vector<std::string> all_plans = ListR2vPlans(dir);
  // Calibration plans: held out of the learning, within the training split.
  std::vector<uint64_t> calibration_ids;
  if (!args.room_type_calibration_plans.empty()) {
    SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.room_type_calibration_plans, "--room-type-calibration-plans", &calibration_ids));
    for (uint64_t i : calibration_ids)
      if (i >= uint64_t(kR2vTrainingPlans))
        return Status::InvalidInput("--room-type-calibration-plans: plan " + std::to_string(i) + " is a validation plan (the training split is 0-" +
                                    std::to_string(kR2vTrainingPlans - 1) + "); hint: 250-299");
  }
  std::vector<std::string> plans, calibration_plans;
  for (size_t i = 0; i < all_plans.size() && i < size_t(kR2vTrainingPlans); ++i) {
    const bool held_out = std::find(calibration_ids.begin(), calibration_ids.end(), uint64_t(i)) != calibration_ids.end();
    if (held_out)
      calibration_plans.push_back(all_plans[i]);
    else if (i < size_t(args.room_type_plans))
      plans.push_back(all_plans[i]);
  }
  if (plans.empty())
    return Status::InvalidInput(FileError(dir, "no R2V plan to learn from", "pass --room-type-plans N with N >= 1, not all of them calibration plans"));
  std::vector<uint64_t> seeds, val_seeds;
  if (!args.room_type_evidence_seeds.empty())
    SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.room_type_evidence_seeds, "--room-type-evidence-seeds", &seeds));
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.val_seeds, "--val-seeds", &val_seeds));
  for (uint64_t s : seeds)
    if (std::find(val_seeds.begin(), val_seeds.end(), s) != val_seeds.end())
      return Status::InvalidInput("--room-type-evidence-seeds: seed " + std::to_string(s) + " is a validation apartment (--val-seeds " +
                                  args.val_seeds + "); hint: 40-79");
  Result<ViewClassifier> classifier = ViewClassifier::Load(args.outdir + "/second", ViewClassifierOptions{});
  if (!classifier.ok()) return classifier.status();
  Result<KnnClassifier> room_knn = KnnClassifier::Load(args.outdir + "/room_type_knn.bin");
  if (!room_knn.ok()) return room_knn.status();
  const std::string path = args.outdir + "/room_type_crf.json";
  Result<RoomTypeModel> model = LoadRoomTypeModel(path);
  if (!model.ok()) return model.status();
  const auto t0 = std::chrono::steady_clock::now();
  int skipped = 0;
  Result<std::vector<RoomTypeTrainingScene>> scenes =
      PlanEvidenceScenes(plans, *classifier, *room_knn, kRoomViewRangeM, kRoomMinObjectFraction, &skipped);
  if (!scenes.ok()) return scenes.status();
  if (scenes->empty()) return Status::InvalidInput(FileError(dir, "none of the plans could be built into an apartment", "check the R2V files"));
  const size_t plan_scenes = scenes->size();
  Result<std::vector<RoomTypeTrainingScene>> generated =
      GeneratedEvidenceScenes(seeds, *classifier, *room_knn, kRoomViewRangeM, kRoomMinObjectFraction);
  if (!generated.ok()) return generated.status();
  for (RoomTypeTrainingScene& s : *generated) scenes->push_back(std::move(s));
  size_t views = 0;
  for (const RoomTypeTrainingScene& s : *scenes) views += s.views.size();
  SEMVOX_INFO("train: room-type evidence: " << plan_scenes << " plan apartments (" << skipped << " plans skipped) and " << seeds.size()
                                            << " generated apartments, " << views << " classified views");
  std::vector<RoomTypeTrainingScene> calibration;
  int calibration_skipped = 0;
  if (!calibration_plans.empty()) {
    Result<std::vector<RoomTypeTrainingScene>> c =
        PlanEvidenceScenes(calibration_plans, *classifier, *room_knn, kRoomViewRangeM, kRoomMinObjectFraction, &calibration_skipped);
    if (!c.ok()) return c.status();
    calibration = std::move(c).value();
    SEMVOX_INFO("train: room-type evidence: weight scale chosen on " << calibration.size() << " held-out plan apartments ("
                                                                     << calibration_skipped << " plans skipped)");
  }
  // The scale is chosen for the energy `semvox run` samples: with the room-shape term when the model is there.
  std::optional<RoomShapeModel> shapes;
  if (Result<RoomShapeModel> s = LoadRoomShapeModel(args.outdir + "/room_shape.json"); s.ok()) shapes = std::move(s).value();
  RoomTypeTrainingOptions rt;
  rt.min_object_fraction = kRoomMinObjectFraction;
  rt.ssvm_runs = args.room_type_ssvm_runs;
  rt.shapes = shapes ? &*shapes : nullptr;
  const std::string report = LearnRoomTypeEvidenceTerms(*scenes, AllRoomTypeVariants(), rt, &*model, &calibration);
  // The provenance names where the learned terms now come from.
  std::string& prov = model->provenance;
  const std::string now = "confusion, SSVM weights and dense-CRF parameters from " + std::to_string(plan_scenes) +
                          " apartments built on " + std::to_string(plans.size()) + " R2V training plans (the first " +
                          std::to_string(args.room_type_plans) + " without " +
                          (calibration_plans.empty() ? std::string("none") : args.room_type_calibration_plans) + ") and generated apartments " +
                          args.room_type_evidence_seeds + " (classified training views, room-type k-NN of room_type_knn.bin); SSVM direction the mean of " +
                          std::to_string(rt.ssvm_runs) + " runs, weight scale chosen on " +
                          (calibration.empty() ? std::string("the same apartments")
                                               : std::to_string(calibration.size()) + " apartments on R2V plans " + args.room_type_calibration_plans) +
                          (shapes ? " with the room-shape term" : "");
  static const std::regex kLearned("confusion, SSVM weights and dense-CRF parameters from .*$");
  prov = std::regex_search(prov, kLearned) ? std::regex_replace(prov, kLearned, now) : prov + "; " + now;
  SEMVOX_RETURN_IF_ERROR(SaveRoomTypeModel(*model, path));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: evidence terms from %zu plan apartments and %zu generated apartments (%zu views, %d plans skipped) in %.1f s\n%s",
              path.c_str(), plan_scenes, seeds.size(), views, skipped, seconds, report.c_str());
  return Status::Ok();
}

Status RunTrainRoomTypeKnn(const TrainArgs& args) {
  std::vector<uint64_t> seeds;
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.train_seeds, "--train-seeds", &seeds));
  const std::string dir = R2vDirectory(args);
  std::vector<std::string> plans;
  if (args.room_type_plans > 0) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
      return Status::InvalidInput(FileError(dir, "no such directory (the R2V plans)", "pass --r2v-dir DIR, or --room-type-plans 0"));
    plans = ListR2vPlans(dir);
    plans.resize(std::min(plans.size(), size_t(std::min(args.room_type_plans, kR2vTrainingPlans))));
  }
  std::optional<ViewClassifier> classifier;
  if (args.room_type_knn_classes == "predicted") {
    Result<ViewClassifier> c = ViewClassifier::Load(args.outdir + "/second", ViewClassifierOptions{});
    if (!c.ok()) return c.status();
    classifier = std::move(c).value();
  }
  const auto t0 = std::chrono::steady_clock::now();
  Result<RoomKnnRows> rows = RoomTypeKnnRows(seeds, plans, classifier ? &*classifier : nullptr);
  if (!rows.ok()) return rows.status();
  Result<KnnClassifier> knn = KnnClassifier::Train(rows->x, RoomDescriptorDims(SecondLevel().num_classes()), rows->y,
                                                   kNumRoomTypeClasses, KnnOptions{});
  if (!knn.ok()) return Status::InvalidInput("room-type k-NN: " + knn.status().message());
  std::error_code ec;
  std::filesystem::create_directories(args.outdir, ec);
  if (ec) return Status::InvalidInput(FileError(args.outdir, "cannot create the output directory", ec.message()));
  const std::string path = args.outdir + "/room_type_knn.bin";
  SEMVOX_RETURN_IF_ERROR(knn->Save(path));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %zu rows (%d from %zu generated apartments, %d from %d R2V plans, %d plans skipped) in %.1f s\n", path.c_str(),
              rows->y.size(), rows->generated_rows, seeds.size(), rows->plan_rows, rows->plans_used, rows->plans_skipped, seconds);
  return Status::Ok();
}

Status RunTrainSegments(const TrainArgs& args) {
  std::vector<uint64_t> val_seeds;
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.val_seeds, "--val-seeds", &val_seeds));
  std::error_code ec;
  std::filesystem::create_directories(args.outdir, ec);
  if (ec) return Status::InvalidInput(FileError(args.outdir, "cannot create the output directory", ec.message()));
  Result<nlohmann::json> j = TrainSegments(args, val_seeds, SecondLevel());
  if (!j.ok()) return j.status();
  return WriteFileAtomic(args.outdir + "/object_segments_report.json", j->dump(2) + "\n");
}

Status RunTrainVoxelCrf(const TrainArgs& args) {
  VoxelCrfTrainingOptions options;
  options.models_dir = args.outdir;
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.voxel_crf_seeds, "--voxel-crf-seeds", &options.seeds));
  options.seeds_text = args.voxel_crf_seeds;
  options.style = args.voxel_crf_style;
  options.epochs = args.voxel_crf_epochs;
  options.appearance_weight = args.voxel_crf_appearance_weight;
  return TrainVoxelCrf(options);
}

Status RunTrain(const TrainArgs& args) {
  std::vector<uint64_t> train_seeds, val_seeds;
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.train_seeds, "--train-seeds", &train_seeds));
  SEMVOX_RETURN_IF_ERROR(ParseSeedList(args.val_seeds, "--val-seeds", &val_seeds));
  if (args.crf_holdout < 0 || size_t(args.crf_holdout) >= train_seeds.size())
    return Status::InvalidInput("--crf-holdout = " + std::to_string(args.crf_holdout) +
                                ". Violated constraint: 0 <= crf-holdout < number of training seeds (" +
                                std::to_string(train_seeds.size()) + ")");
  // --view-plans: the plans are listed before anything is trained, so a wrong directory fails at once.
  std::vector<std::string> view_plans;
  if (args.view_plans > 0) {
    const std::string dir = R2vDirectory(args);
    std::error_code dir_ec;
    if (!std::filesystem::is_directory(dir, dir_ec))
      return Status::InvalidInput(FileError(dir, "no such directory (the R2V plans)", "pass --r2v-dir DIR, or --view-plans 0"));
    view_plans = ListR2vPlans(dir);
    if (view_plans.empty()) return Status::InvalidInput(FileError(dir, "holds no plan_*.txt", "pass --r2v-dir DIR, or --view-plans 0"));
    view_plans.resize(std::min(view_plans.size(), size_t(std::min(args.view_plans, kR2vTrainingPlans))));
  }
  std::error_code ec;
  std::filesystem::create_directories(args.outdir, ec);
  if (ec) return Status::InvalidInput(FileError(args.outdir, "cannot create the output directory", ec.message()));
  const std::vector<LabelLevel> levels = {Nyu4Level(), SecondLevel()};
  ViewClassifierOptions options;
  TrainingViewsOptions views;
  if (!ParseTrainingStyle(args.style, &views.style))
    return Status::InvalidInput("--style = '" + args.style + "': expected randomised or flat");
  std::vector<TrainingSet> sets(levels.size());
  int train_views = 0;
  // Room-type evidence: descriptors from the ground-truth second-level classes of every training view.
  const LabelLevel& room_level = levels[1];
  std::vector<float> room_rows;
  std::vector<int> room_labels;
  std::vector<uint64_t> room_row_seeds;  // Apartment of each row (room-type CRF: leave-one-apartment-out k-NN).
  std::vector<RoomViewRecord> room_records;  // Classified views of the CRF seeds (room-type CRF training).
  auto add_room_row = [&](const LabelledView& v) {
    if (AddRoomKnnRow(v, room_level.Map(*v.nyu40), room_level.num_classes(), &room_rows, &room_labels)) room_row_seeds.push_back(v.seed);
  };
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<uint64_t> crf_seeds(train_seeds.end() - args.crf_holdout, train_seeds.end());
  train_seeds.resize(train_seeds.size() - size_t(args.crf_holdout));
  for (uint64_t seed : train_seeds) {
    SEMVOX_RETURN_IF_ERROR(ForEachSegmentedView(seed, views, options, [&](const LabelledView& v, const Superpixels& sp, const ViewObservations& obs) {
      for (size_t l = 0; l < levels.size(); ++l)
        AddTrainingSuperpixels(sp, obs, levels[l].Map(*v.nyu40), options.min_label_purity, &sets[l]);
      add_room_row(v);
      ++train_views;
      return Status::Ok();
    }));
    SEMVOX_INFO("train: seed " << seed << ", " << train_views << " views so far");
  }
  // Apartments on real layouts (--view-plans): their views' superpixels join the per-view classifiers' rows
  // (not the room-type k-NN's). Plan k draws its furniture, colours and views from kPlanViewSeedBase + k.
  int plan_views = 0, plans_used = 0, plans_skipped = 0;
  if (!view_plans.empty()) {
    for (size_t k = 0; k < view_plans.size(); ++k) {
      Result<Apartment> apartment = TrainingPlanApartment(view_plans[k], k);
      if (!apartment.ok()) {
        ++plans_skipped;
        SEMVOX_INFO("train: plan " << view_plans[k] << " skipped: " << apartment.status().message());
        continue;
      }
      ++plans_used;
      SEMVOX_RETURN_IF_ERROR(ForEachViewOfApartment(*apartment, kPlanViewSeedBase + k, views, [&](const LabelledView& lv) {
        return SegmentView(lv, options, [&](const LabelledView& v, const Superpixels& sp, const ViewObservations& obs) {
          for (size_t l = 0; l < levels.size(); ++l)
            AddTrainingSuperpixels(sp, obs, levels[l].Map(*v.nyu40), options.min_label_purity, &sets[l]);
          ++plan_views;
          return Status::Ok();
        });
      }));
    }
    SEMVOX_INFO("train: " << plan_views << " views of " << plans_used << " R2V plan apartments (" << plans_skipped << " skipped)");
  }
  std::vector<ViewClassifier> classifiers;
  nlohmann::json report;
  // The effective configuration, beside the outputs.
  report["options"] = {
      {"superpixels", {{"region_size_px", options.superpixels.region_size_px}, {"compactness", options.superpixels.compactness},
                       {"iterations", options.superpixels.iterations},
                       {"min_element_size_percent", options.superpixels.min_element_size_percent}}},
      {"observations", {{"min_depth_fraction", options.observations.min_depth_fraction},
                        {"edge_gradient_min", options.observations.edge_gradient_min},
                        {"vanishing_angle_max_deg", options.observations.vanishing_angle_max_deg}}},
      {"knn", {{"k", options.knn.k}, {"probability_floor", options.knn.probability_floor}, {"standardise", options.knn.standardise}}},
      {"crf_scales", {{"colour_scale_lab", options.crf.colour_scale_lab}, {"distance_scale_m", options.crf.distance_scale_m}}},
      {"loopy", {{"max_iterations", options.loopy.max_iterations}, {"damping", options.loopy.damping}, {"tolerance", options.loopy.tolerance}}},
      {"min_label_purity", options.min_label_purity},
      {"views", {{"style", TrainingStyleName(views.style)}, {"width", views.width}, {"height", views.height}, {"horizontal_fov_deg", views.horizontal_fov_deg},
                 {"eye_height_m", views.eye_height_m}, {"pitch_deg", views.pitch_deg}, {"yaws_per_room", views.yaws_per_room},
                 {"min_hit_fraction", views.min_hit_fraction}, {"min_mean_depth_m", views.min_mean_depth_m}}},
      {"max_rows", args.max_rows},
      {"crf_holdout", args.crf_holdout},
      {"room_min_object_fraction", kRoomMinObjectFraction}};
  report["train_seeds"] = args.train_seeds;
  report["crf_holdout_seeds"] = crf_seeds;
  report["val_seeds"] = args.val_seeds;
  report["train_views"] = train_views;
  report["view_plans"] = {{"plans", args.view_plans}, {"used", plans_used}, {"skipped", plans_skipped}, {"views", plan_views}};
  for (size_t l = 0; l < levels.size(); ++l) {
    report["levels"][levels[l].name]["train_rows_image"] = sets[l].image_labels.size();
    report["levels"][levels[l].name]["train_rows_image_3d"] = sets[l].full_labels.size();
    Subsample(args.max_rows, &sets[l]);
    Result<ViewClassifier> clf = ViewClassifier::Train(sets[l], levels[l].num_classes(), options);
    if (!clf.ok()) return clf.status();
    classifiers.push_back(std::move(clf).value());
  }
  // CRF weights on the held-out seeds.
  std::vector<std::vector<CrfTrainingGraph>> tree_graphs(levels.size()), union_graphs(levels.size());
  for (uint64_t seed : crf_seeds) {
    SEMVOX_RETURN_IF_ERROR(ForEachSegmentedView(seed, views, options, [&](const LabelledView& v, const Superpixels& sp, const ViewObservations& obs) {
      for (size_t l = 0; l < levels.size(); ++l) {
        tree_graphs[l].emplace_back();
        union_graphs[l].emplace_back();
        SEMVOX_RETURN_IF_ERROR(classifiers[l].CrfTrainingGraphs(sp, obs, levels[l].Map(*v.nyu40), &tree_graphs[l].back(),
                                                                &union_graphs[l].back()));
      }
      // Room-type CRF: this view's descriptor from its predicted second-level classes (tree CRF).
      Result<ViewClassification> room_c = classifiers[1].Classify(sp, obs);
      if (!room_c.ok()) return room_c.status();
      room_records.push_back(MakeRoomViewRecord(v, PixelLabels(room_c->superpixels, room_c->tree_labels),
                                                room_level.num_classes(), RoomObjectClasses(room_level.class_names), kRoomViewRangeM));
      add_room_row(v);
      return Status::Ok();
    }));
  }
  for (size_t l = 0; l < levels.size() && !crf_seeds.empty(); ++l) {
    CrfLearningOptions tree_learning;
    tree_learning.learn_distance_weight = false;  // Eq. 6 has no distance term.
    CrfLearningSummary tree_summary, union_summary;
    Result<ViewCrfOptions> tree = LearnCrfWeights(tree_graphs[l], options.crf, tree_learning, &tree_summary);
    if (!tree.ok()) return tree.status();
    Result<ViewCrfOptions> uni = LearnCrfWeights(union_graphs[l], options.union_crf, CrfLearningOptions{}, &union_summary);
    if (!uni.ok()) return uni.status();
    classifiers[l].SetCrfOptions(*tree, *uni);
    nlohmann::json& j = report["levels"][levels[l].name]["crf_weights"];
    j["tree"] = {{"unary", tree->unary_weight}, {"colour", tree->colour_weight},
                 {"nlpl_initial", tree_summary.initial_nlpl}, {"nlpl_final", tree_summary.final_nlpl}};
    j["union"] = {{"unary", uni->unary_weight}, {"colour", uni->colour_weight}, {"distance", uni->distance_weight},
                  {"nlpl_initial", union_summary.initial_nlpl}, {"nlpl_final", union_summary.final_nlpl}};
    SEMVOX_INFO("train: " << levels[l].name << " tree CRF weights w_u " << tree->unary_weight << " w_c " << tree->colour_weight
                          << "; union w_u " << uni->unary_weight << " w_c " << uni->colour_weight << " w_d " << uni->distance_weight);
  }
  for (size_t l = 0; l < levels.size(); ++l) SEMVOX_RETURN_IF_ERROR(classifiers[l].Save(args.outdir + "/" + levels[l].name));
  Result<KnnClassifier> room_knn = KnnClassifier::Train(room_rows, RoomDescriptorDims(room_level.num_classes()), room_labels,
                                                        kNumRoomTypeClasses, KnnOptions{});
  if (!room_knn.ok()) return Status::InvalidInput("room-type k-NN: " + room_knn.status().message());
  SEMVOX_RETURN_IF_ERROR(room_knn->Save(args.outdir + "/room_type_knn.bin"));
  report["room_type"]["train_views"] = room_labels.size();
  {  // Room-type CRF: statistics from all training seeds (+ R2V fixtures), the rest from the CRF seeds.
    RoomTypeTrainingOptions rt;
    rt.min_object_fraction = kRoomMinObjectFraction;
    rt.r2v_dir = R2vDirectory(args);
    if (std::error_code ec; !std::filesystem::is_directory(rt.r2v_dir, ec))
      SEMVOX_WARN("train: " << rt.r2v_dir << ": no R2V plans there; the room-type object statistics go without them "
                            "(hint: --r2v-dir DIR, or run from the source tree's root)");
    std::vector<uint64_t> stat_seeds = train_seeds;
    stat_seeds.insert(stat_seeds.end(), crf_seeds.begin(), crf_seeds.end());
    RoomTypeTrainingSummary rts;
    Result<RoomTypeModel> rtm = TrainRoomTypeModel(room_records, room_rows, room_labels, room_row_seeds,
                                                   RoomDescriptorDims(room_level.num_classes()), stat_seeds, rt, &rts);
    if (!rtm.ok()) return rtm.status();
    SEMVOX_RETURN_IF_ERROR(SaveRoomTypeModel(*rtm, args.outdir + "/room_type_crf.json"));
    report["room_type_crf"] = {{"provenance", rtm->provenance}, {"evidence_apartments", rts.evidence_scenes},
                               {"statistics_apartments", rts.statistics_apartments}, {"r2v_plans", rts.r2v_plans},
                               {"weights", rts.report}};
    SEMVOX_INFO("train: room-type CRF\n" << rts.report);
  }
  const std::vector<bool> object_classes = RoomObjectClasses(room_level.class_names);
  int room_correct = 0, room_views = 0, room_other = 0;
  // Validation: pixel-wise confusion per level and method.
  std::vector<std::array<ConfusionMatrix, 3>> cms;
  for (const LabelLevel& level : levels)
    cms.push_back({ConfusionMatrix(level.num_classes()), ConfusionMatrix(level.num_classes()), ConfusionMatrix(level.num_classes())});
  int val_views = 0;
  std::vector<int> union_converged(levels.size(), 0);  // Views whose loopy BP met its tolerance.
  for (uint64_t seed : val_seeds) {
    SEMVOX_RETURN_IF_ERROR(ForEachSegmentedView(seed, views, options, [&](const LabelledView& v, const Superpixels& sp, const ViewObservations& obs) {
      for (size_t l = 0; l < levels.size(); ++l) {
        Result<ViewClassification> c = classifiers[l].Classify(sp, obs);
        if (!c.ok()) return c.status();
        const Image<int32_t> truth = levels[l].Map(*v.nyu40);
        cms[l][0].AddImages(truth, PixelLabels(c->superpixels, c->knn_labels));
        cms[l][1].AddImages(truth, PixelLabels(c->superpixels, c->tree_labels));
        cms[l][2].AddImages(truth, PixelLabels(c->superpixels, c->union_labels));
        union_converged[l] += c->union_bp.converged;
        if (l == 1 && v.room_type >= 1 && v.room_type <= kNumRoomTypeClasses) {
          // Room-type evidence from the predicted (tree CRF) second-level classes.
          const Image<int32_t> predicted = PixelLabels(c->superpixels, c->tree_labels);
          const std::vector<double> p = RoomTypeProbabilities(
              *room_knn, RoomViewDescriptor(*v.view, predicted, room_level.num_classes()),
              ObjectPixelFraction(*v.view, predicted, object_classes), kRoomMinObjectFraction);
          const int best = int(std::max_element(p.begin(), p.end()) - p.begin());
          room_correct += best == v.room_type - 1;
          room_other += best == kOtherRoomTypeIndex && v.room_type - 1 != kOtherRoomTypeIndex;
          ++room_views;
        }
      }
      ++val_views;
      return Status::Ok();
    }));
  }
  // The same validation seeds in the other style (flat <-> randomised), union CRF, so that both are reported.
  {
    TrainingViewsOptions other = views;
    other.style = views.style == TrainingStyle::kFlat ? TrainingStyle::kRandomised : TrainingStyle::kFlat;
    std::vector<ConfusionMatrix> other_cms;
    for (const LabelLevel& level : levels) other_cms.emplace_back(level.num_classes());
    int other_views = 0;
    for (uint64_t seed : val_seeds) {
      SEMVOX_RETURN_IF_ERROR(ForEachSegmentedView(seed, other, options, [&](const LabelledView& v, const Superpixels& sp, const ViewObservations& obs) {
        for (size_t l = 0; l < levels.size(); ++l) {
          Result<ViewClassification> c = classifiers[l].Classify(sp, obs);
          if (!c.ok()) return c.status();
          other_cms[l].AddImages(levels[l].Map(*v.nyu40), PixelLabels(c->superpixels, c->union_labels));
        }
        ++other_views;
        return Status::Ok();
      }));
    }
    const std::string key = std::string("union_crf_val_") + TrainingStyleName(other.style);
    for (size_t l = 0; l < levels.size(); ++l) {
      report["levels"][levels[l].name][key] = Scores(other_cms[l], levels[l]);
      report["levels"][levels[l].name][key]["views"] = other_views;
      std::printf("%s, union CRF on the %s-style validation views (%d): global %.3f  average %.3f\n", levels[l].name.c_str(),
                  TrainingStyleName(other.style), other_views, other_cms[l].GlobalAccuracy(), other_cms[l].AverageRecall());
    }
  }
  report["val_views"] = val_views;
  report["room_type"]["val_views"] = room_views;
  report["room_type"]["accuracy_per_view"] = room_views > 0 ? std::round(1e4 * room_correct / room_views) / 1e4 : 0.0;
  report["room_type"]["other_fallbacks"] = room_other;
  std::printf("room type per view: %d / %d correct (%.3f), %d sent to other for too little evidence\n", room_correct,
              room_views, room_views > 0 ? double(room_correct) / room_views : 0.0, room_other);
  const char* methods[3] = {"knn", "tree_crf", "union_crf"};
  for (size_t l = 0; l < levels.size(); ++l) {
    std::printf("%s (%d classes), %d validation views:\n", levels[l].name.c_str(), levels[l].num_classes(), val_views);
    for (int k = 0; k < 3; ++k) {
      report["levels"][levels[l].name][methods[k]] = Scores(cms[l][size_t(k)], levels[l]);
      if (k == 2) report["levels"][levels[l].name][methods[k]]["loopy_bp_converged_views"] = union_converged[l];
      std::printf("  %-9s global %.3f  average %.3f\n", methods[k], cms[l][size_t(k)].GlobalAccuracy(), cms[l][size_t(k)].AverageRecall());
    }
  }
  // Support / clutter / other (src/objects): RBF SVM on the support/clutter paper's Table 2 features
  // of every training view, scored with and without the dense CRF on the validation views.
  {
    SupportTrainingOptions support;
    support.train_seeds = train_seeds;
    support.train_seeds.insert(support.train_seeds.end(), crf_seeds.begin(), crf_seeds.end());
    support.val_seeds = val_seeds;
    SupportTrainingSummary summary;
    Result<SupportClutterClassifier> support_clf = TrainSupportClutter(support, &summary);
    if (!support_clf.ok()) return support_clf.status();
    SEMVOX_RETURN_IF_ERROR(support_clf->Save(args.outdir + "/support_clutter.svm"));
    report["support_clutter"] = summary.ToJson();
    std::printf("support/clutter, %d validation views: support recall %.3f IoU %.3f, clutter recall %.3f IoU %.3f (SVM + dense CRF)\n",
                summary.val_views, ClassRecall(summary.crf, kSupportSurface), ClassIoU(summary.crf, kSupportSurface),
                ClassRecall(summary.crf, kClutter), ClassIoU(summary.crf, kClutter));
    // Generic object proposals (MST-CRF paper, Sec. 4) with the NYU-4 classifier's probabilities.
    ProposalTrainingOptions proposal;
    proposal.train_seeds = support.train_seeds;
    proposal.val_seeds = val_seeds;
    ProposalTrainingSummary proposal_summary;
    Result<ObjectProposer> proposer = TrainObjectProposer(proposal, classifiers[0], &proposal_summary);
    if (!proposer.ok()) return proposer.status();
    SEMVOX_RETURN_IF_ERROR(proposer->Save(args.outdir + "/object_proposals.svm"));
    report["object_proposals"] = proposal_summary.ToJson();
    std::printf("object proposals: detection rate %.3f at 5 false positives per image (sampled), speed-up of features + SVM x%.2f\n",
                proposal_summary.sampled.DetectionRateAt(5.0), proposal_summary.ToJson()["speedup_features_svm"].get<double>());
  }
  {  // Object segments classified by shape (the Voxel-CRF's segment term).
    Result<nlohmann::json> j = TrainSegments(args, val_seeds, levels[1]);
    if (!j.ok()) return j.status();
    report["object_segments"] = *j;
  }
  SEMVOX_INFO("train: " << std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count())
                         << " s; models and train_report.json in " << args.outdir);
  return WriteFileAtomic(args.outdir + "/train_report.json", report.dump(2) + "\n");
}

}  // namespace semvox
