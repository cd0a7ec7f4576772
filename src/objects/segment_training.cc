#include "objects/segment_training.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>

#include "core/labels.h"
#include "eval/evaluate.h"
#include "mapping/voxelizer.h"
#include "scenegen/apartment.h"

namespace semvox {

namespace {

// The entry with the most counts (the first of equals, in key order).
std::map<int, int>::const_iterator Majority(const std::map<int, int>& counts) {
  return std::max_element(counts.begin(), counts.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
}

}  // namespace

std::string SegmentTrainingSummary::ToText(const LabelLevel& level) const {
  std::string s;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "object segments: %d training, %d validation; validation segment accuracy %.3f, voxel-weighted global %.3f average %.3f\n",
                train_segments, val_segments, val_segment_accuracy, val_voxels.GlobalAccuracy(), val_voxels.AverageRecall());
  s += buf;
  for (int c = 0; c < level.num_classes(); ++c) {
    const double r = val_voxels.Recall(c);
    if (std::isnan(r)) continue;
    std::snprintf(buf, sizeof(buf), "  %-16s recall %.3f\n", level.class_names[size_t(c)].c_str(), r);
    s += buf;
  }
  if (item_train_rows > 0) {
    // Items: the share of voxels in groups that are objects of their own given their id, and of those in
    // groups given an id that are that object.
    int64_t items_true = 0, items_right = 0, called = 0, called_right = 0;
    for (int t = 0; t < item_val_voxels.m; ++t)
      for (int p = 0; p < item_val_voxels.m; ++p) {
        const int64_t n = item_val_voxels.counts[size_t(t) * size_t(item_val_voxels.m) + size_t(p)];
        if (t > 0) items_true += n, items_right += t == p ? n : 0;
        if (p > 0) called += n, called_right += t == p ? n : 0;
      }
    std::snprintf(buf, sizeof(buf), "items on top: %d training, %d validation groups; voxels right %.3f, item recall %.3f, precision %.3f\n",
                  item_train_rows, item_val_rows, item_val_voxels.GlobalAccuracy(), items_true ? double(items_right) / double(items_true) : 0.0,
                  called ? double(called_right) / double(called) : 0.0);
    s += buf;
  }
  if (other_train_rows > 0) {
    std::snprintf(buf, sizeof(buf), "other labels: %d training, %d validation rows; validation voxels %.3f, average %.3f\n", other_train_rows,
                  other_val_rows, other_val_voxels.GlobalAccuracy(), other_val_voxels.AverageRecall());
    s += buf;
    for (int id = 1; id < kNumNyu40; ++id) {
      const double r = other_val_voxels.Recall(id);
      if (std::isnan(r)) continue;
      std::snprintf(buf, sizeof(buf), "  %-16s recall %.3f\n", Nyu40Labels()[size_t(id)].name, r);
      s += buf;
    }
  }
  return s;
}

Status LabelledSegments(uint64_t seed, const SegmentTrainingOptions& options, std::vector<float>* features,
                        std::vector<int>* classes, std::vector<int>* voxels, OtherRows* other, OtherRows* items) {
  ApartmentOptions ao;
  ao.seed = seed;
  ao.shape_variety = options.scans.style == TrainingStyle::kRandomised;
  Result<Apartment> apartment = GenerateApartment(ao);
  if (!apartment.ok()) return apartment.status();
  Result<Scene> scene = MakeTrainingScan(*apartment, seed, options.scans);
  if (!scene.ok()) return scene.status();
  VoxelizeOptions vo;
  vo.voxel_size_m = options.voxel_size_m;
  // With free space as `semvox run` has it: the furniture-front test (SegmentOptions::front_*) reads it.
  Result<VoxelMap> map = Voxelize(*scene, vo);
  if (!map.ok()) return map.status();
  const SegmentationResult seg = SegmentObjects(map->grid, map->floor_z, map->ceiling_z, map->ceiling_found, options.segments);
  const VoxelLabels truth = VoxelizeLabeledMesh(apartment->mesh, options.voxel_size_m);
  const LabelLevel level = SecondLevel();
  for (const ObjectSegment& s : seg.segments) {
    // Each voxel's ground-truth NYU40 id (0: none), looked up once for the three kinds of rows.
    std::vector<int> gt(s.voxels.size(), 0);
    for (size_t i = 0; i < s.voxels.size(); ++i) {
      const auto c = map->grid.Cell(s.voxels[i]);
      const auto it = truth.find(map->grid.KeyOf(c[0], c[1], c[2]).Pack());
      if (it != truth.end() && it->second > 0 && it->second < kNumNyu40) gt[i] = it->second;
    }
    if (other) {
      std::vector<uint32_t> mine;
      std::map<int, int> ids;
      for (size_t i = 0; i < s.voxels.size(); ++i)
        if (IsOtherNyu40(gt[i])) mine.push_back(s.voxels[i]), ++ids[gt[i]];
      if (int(mine.size()) >= options.other_min_voxels) {
        const OtherFeatureVector f = OtherFeatures(map->grid, seg, s, mine);
        other->features.insert(other->features.end(), f.begin(), f.end());
        other->ids.push_back(Majority(ids)->first);
        other->voxels.push_back(int(mine.size()));
      }
    }
    if (items) {
      // Each item on top against the rest of its segment, by their most frequent ground-truth ids.
      for (const std::vector<uint32_t>& group : ItemsOnTop(map->grid, seg, s, options.other_min_voxels)) {
        std::map<int, int> in, rest;
        int labelled_in = 0;
        for (size_t i = 0; i < s.voxels.size(); ++i) {
          if (!gt[i]) continue;
          if (std::binary_search(group.begin(), group.end(), s.voxels[i])) ++in[gt[i]], ++labelled_in;
          else ++rest[gt[i]];
        }
        if (labelled_in * 2 < int(group.size())) continue;
        const int item = Majority(in)->first;
        const int cls = !rest.empty() && Majority(rest)->first == item ? 0 : item;
        const OtherFeatureVector f = OtherFeatures(map->grid, seg, s, group);
        items->features.insert(items->features.end(), f.begin(), f.end());
        items->ids.push_back(cls);
        items->voxels.push_back(int(group.size()));
      }
    }
    std::map<int, int> votes;
    int labelled = 0;
    for (int id : gt) {
      const int cls = id > 0 ? level.class_of_nyu40[size_t(id)] : -1;
      if (cls < 0) continue;
      ++votes[cls];
      ++labelled;
    }
    if (labelled == 0 || labelled * 4 < int(s.voxels.size())) continue;
    const auto best = Majority(votes);
    if (best->second < options.min_purity * labelled) continue;
    features->insert(features->end(), s.features.begin(), s.features.end());
    classes->push_back(best->first);
    voxels->push_back(int(s.voxels.size()));
  }
  return Status::Ok();
}

Result<SegmentClassifier> TrainSegmentClassifier(const SegmentTrainingOptions& options, SegmentTrainingSummary* summary,
                                                 std::optional<OtherLabeller>* other, std::optional<ItemLabeller>* items) {
  const auto t0 = std::chrono::steady_clock::now();
  const LabelLevel level = SecondLevel();
  std::vector<float> features;
  std::vector<int> classes, voxels;
  OtherRows other_rows, item_rows;
  for (uint64_t seed : options.train_seeds)
    SEMVOX_RETURN_IF_ERROR(
        LabelledSegments(seed, options, &features, &classes, &voxels, other ? &other_rows : nullptr, items ? &item_rows : nullptr));
  if (classes.empty()) return Status::InvalidInput("object segments: no labelled training segment");
  SegmentTrainingSummary s;
  if (other) {
    if (other_rows.ids.empty()) return Status::InvalidInput("other labels: no training segment holds an \"other\" object");
    s.other_train_rows = int(other_rows.ids.size());
    Result<KnnClassifier> knn = KnnClassifier::Train(std::move(other_rows.features), kNumOtherFeatures, other_rows.ids, kNumNyu40, options.knn);
    if (!knn.ok()) return knn.status();
    other->emplace(std::move(knn).value());
    s.other_val_voxels = ConfusionMatrix(kNumNyu40);
  }
  if (items) {
    if (item_rows.ids.empty()) return Status::InvalidInput("items on top: no training segment has any");
    s.item_train_rows = int(item_rows.ids.size());
    Result<KnnClassifier> knn = KnnClassifier::Train(std::move(item_rows.features), kNumOtherFeatures, item_rows.ids, kNumNyu40, options.knn);
    if (!knn.ok()) return knn.status();
    items->emplace(std::move(knn).value());
    s.item_val_voxels = ConfusionMatrix(kNumNyu40);
  }
  std::optional<SegmentClassifier> clf;
  if (options.classifier == SegmentClassifierKind::kForest) {
    Result<RandomForest> rf = RandomForest::Train(features, kNumSegmentFeatures, classes, level.num_classes(), options.forest);
    if (!rf.ok()) return rf.status();
    clf.emplace(std::move(rf).value());
  } else {
    Result<KnnClassifier> knn = KnnClassifier::Train(features, kNumSegmentFeatures, classes, level.num_classes(), options.knn);
    if (!knn.ok()) return knn.status();
    clf.emplace(std::move(knn).value());
  }
  s.train_segments = int(classes.size());
  s.val_voxels = ConfusionMatrix(level.num_classes());
  int correct = 0;
  for (uint64_t seed : options.val_seeds) {
    std::vector<float> vf;
    std::vector<int> vc, vv;
    OtherRows vo, vi;
    SEMVOX_RETURN_IF_ERROR(LabelledSegments(seed, options, &vf, &vc, &vv, other ? &vo : nullptr, items ? &vi : nullptr));
    // Each row's voxels counted with the labeller's id.
    auto score = [](const OtherRows& rows, const auto& labeller, ConfusionMatrix* m, int* n) {
      for (size_t i = 0; i < rows.ids.size(); ++i) {
        const int id = labeller.Label({rows.features.data() + i * kNumOtherFeatures, size_t(kNumOtherFeatures)});
        for (int k = 0; k < rows.voxels[i]; ++k) m->Add(rows.ids[i], id);
        ++*n;
      }
    };
    if (items) score(vi, **items, &s.item_val_voxels, &s.item_val_rows);
    if (other) score(vo, **other, &s.other_val_voxels, &s.other_val_rows);
    for (size_t i = 0; i < vc.size(); ++i) {
      const std::vector<double> p = clf->Probabilities({vf.data() + i * kNumSegmentFeatures, size_t(kNumSegmentFeatures)});
      const int best = int(std::max_element(p.begin(), p.end()) - p.begin());
      correct += best == vc[i];
      for (int k = 0; k < vv[i]; ++k) s.val_voxels.Add(vc[i], best);
      ++s.val_segments;
    }
  }
  s.val_segment_accuracy = s.val_segments > 0 ? double(correct) / s.val_segments : 0.0;
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (summary) *summary = s;
  return std::move(*clf);
}

}  // namespace semvox
