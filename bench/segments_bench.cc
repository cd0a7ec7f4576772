// Object segments classified by shape (objects/object_segments.h): trains the k-NN on generated apartments
// and/or classifies the segments of a scan, printing each segment with its shape and class.
//
//   segments_bench --train 0-39 --val 100-109 [-o DIR]           # k-NN into DIR/object_segments.knn
//   segments_bench --train 0-39 --dump SEGMENTS.tsv                # only the labelled segments, no training
//   segments_bench --model MODEL.knn|MODEL.forest --scan INPUT [--up z] [--voxel M]  # segments of a real scan
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "pipeline/semantic_options.h"
#include "io/load_scene.h"
#include "mapping/scene_frame.h"
#include "mapping/voxelizer.h"
#include "objects/random_forest.h"
#include "objects/svm_classifier.h"
#include "objects/segment_training.h"

using namespace semvox;

namespace {

struct Rows {
  std::vector<float> x;
  std::vector<int> y, voxels;
};

// seed/scan, class name, voxels, features (the --dump format).
bool ReadRows(const std::string& path, const LabelLevel& level, Rows* rows) {
  FILE* f = std::fopen(path.c_str(), "r");
  if (!f) return false;
  char line[4096];
  while (std::fgets(line, sizeof line, f)) {
    char* save = nullptr;
    strtok_r(line, "\t\n", &save);
    const std::string name = strtok_r(nullptr, "\t\n", &save);
    const int voxels = std::atoi(strtok_r(nullptr, "\t\n", &save));
    int cls = -1;
    for (size_t c = 0; c < level.class_names.size(); ++c)
      if (level.class_names[c] == name) cls = int(c);
    std::vector<float> x;
    for (char* t = strtok_r(nullptr, "\t\n", &save); t; t = strtok_r(nullptr, "\t\n", &save)) x.push_back(float(std::atof(t)));
    if (cls < 0 || int(x.size()) != kNumSegmentFeatures) continue;
    rows->x.insert(rows->x.end(), x.begin(), x.end());
    rows->y.push_back(cls);
    rows->voxels.push_back(voxels);
  }
  std::fclose(f);
  return true;
}

void Score(const char* name, const Rows& r, int K, const std::function<std::vector<double>(const float*)>& predict) {
  std::vector<double> correct(size_t(K), 0), total(size_t(K), 0);
  double seg_ok = 0, vox_ok = 0, vox = 0;
  for (size_t i = 0; i < r.y.size(); ++i) {
    const std::vector<double> p = predict(&r.x[i * kNumSegmentFeatures]);
    const int best = int(std::max_element(p.begin(), p.end()) - p.begin());
    seg_ok += best == r.y[i];
    vox_ok += best == r.y[i] ? r.voxels[i] : 0;
    vox += r.voxels[i];
    total[size_t(r.y[i])] += r.voxels[i];
    correct[size_t(r.y[i])] += best == r.y[i] ? r.voxels[i] : 0;
  }
  double mean = 0;
  int classes = 0;
  for (int c = 0; c < K; ++c)
    if (total[size_t(c)] > 0) mean += correct[size_t(c)] / total[size_t(c)], ++classes;
  std::printf("  %-8s %4zu segments: segment accuracy %.3f, voxel-weighted %.3f, class mean %.3f\n", name, r.y.size(),
              seg_ok / double(std::max<size_t>(1, r.y.size())), vox_ok / std::max(1.0, vox), mean / std::max(1, classes));
}

// --compare TRAIN.tsv,VAL.tsv[,SCAN.tsv]: k-NN and SVM settings trained on the same rows.
int Compare(const std::string& files, const LabelLevel& level) {
  std::vector<std::string> paths;
  for (size_t a = 0, b; a <= files.size(); a = b + 1) {
    b = files.find(',', a);
    if (b == std::string::npos) b = files.size();
    paths.push_back(files.substr(a, b - a));
  }
  std::vector<Rows> sets(paths.size());
  for (size_t i = 0; i < paths.size(); ++i)
    if (!ReadRows(paths[i], level, &sets[i])) return 1;
  const int K = level.num_classes();
  for (int k : {10, 25}) {
    KnnOptions o;
    o.k = k;
    Result<KnnClassifier> knn = KnnClassifier::Train(sets[0].x, kNumSegmentFeatures, sets[0].y, K, o);
    if (!knn.ok()) return 1;
    std::printf("k-NN k = %d\n", k);
    for (size_t i = 1; i < sets.size(); ++i)
      Score(paths[i].c_str(), sets[i], K, [&](const float* x) { return knn->Probabilities({x, size_t(kNumSegmentFeatures)}); });
  }
  for (int mtry : {4, 6, 8})
    for (bool balance : {false, true})
      for (uint64_t seed : {1, 2}) {
        RandomForestOptions o;
        o.features_per_split = mtry, o.balance_classes = balance, o.seed = seed;
        if (const char* t = std::getenv("SEGMENTS_BENCH_TREES")) o.trees = std::atoi(t);
        if (const char* t = std::getenv("SEGMENTS_BENCH_MIN_LEAF")) o.min_leaf = std::atoi(t);
        const auto t0 = std::chrono::steady_clock::now();
        Result<RandomForest> rf = RandomForest::Train(sets[0].x, kNumSegmentFeatures, sets[0].y, K, o);
        if (!rf.ok()) return 1;
        std::printf("random forest: %d trees, %d features per split, %s, seed %d (%zu nodes, %.1f s)\n", o.trees, mtry,
                    balance ? "balanced" : "unbalanced", int(seed), rf->num_nodes(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        for (size_t i = 1; i < sets.size(); ++i)
          Score(paths[i].c_str(), sets[i], K, [&](const float* x) { return rf->Probabilities({x, size_t(kNumSegmentFeatures)}); });
      }
  if (std::getenv("SEGMENTS_BENCH_NO_SVM")) return 0;
  // SVM: classes with at least two rows only (libsvm's probability cross-validation).
  std::vector<int> count(size_t(K), 0), remap(size_t(K), -1), back;
  for (int y : sets[0].y) ++count[size_t(y)];
  for (int c = 0; c < K; ++c)
    if (count[size_t(c)] >= 2) remap[size_t(c)] = int(back.size()), back.push_back(c);
  Rows t;
  for (size_t i = 0; i < sets[0].y.size(); ++i)
    if (remap[size_t(sets[0].y[i])] >= 0) {
      t.x.insert(t.x.end(), &sets[0].x[i * kNumSegmentFeatures], &sets[0].x[(i + 1) * kNumSegmentFeatures]);
      t.y.push_back(remap[size_t(sets[0].y[i])]);
    }
  // Standardise as the k-NN does.
  std::vector<double> mu(kNumSegmentFeatures, 0), sd(kNumSegmentFeatures, 0);
  const size_t n = t.y.size();
  for (size_t i = 0; i < n; ++i)
    for (int d = 0; d < kNumSegmentFeatures; ++d) mu[size_t(d)] += t.x[i * kNumSegmentFeatures + size_t(d)] / double(n);
  for (size_t i = 0; i < n; ++i)
    for (int d = 0; d < kNumSegmentFeatures; ++d) sd[size_t(d)] += std::pow(t.x[i * kNumSegmentFeatures + size_t(d)] - mu[size_t(d)], 2) / double(n);
  for (double& v : sd) v = std::max(1e-6, std::sqrt(v));
  auto standardise = [&](const float* x, float* z) {
    for (int d = 0; d < kNumSegmentFeatures; ++d) z[d] = float((x[d] - mu[size_t(d)]) / sd[size_t(d)]);
  };
  for (size_t i = 0; i < n; ++i) standardise(&t.x[i * kNumSegmentFeatures], &t.x[i * kNumSegmentFeatures]);
  for (double c : {1.0, 4.0, 16.0})
    for (double g : {0.02, 0.06, 0.2}) {
      SvmOptions o;
      o.c = c;
      o.gamma = g;
      Result<SvmClassifier> svm = SvmClassifier::Train(t.x, kNumSegmentFeatures, t.y, int(back.size()), o);
      if (!svm.ok()) {
        std::fprintf(stderr, "svm: %s\n", svm.status().message().c_str());
        return 1;
      }
      std::printf("SVM C = %g, gamma = %g (%d support vectors)\n", c, g, svm->num_support_vectors());
      for (size_t i = 1; i < sets.size(); ++i)
        Score(paths[i].c_str(), sets[i], K, [&](const float* x) {
          float z[kNumSegmentFeatures];
          standardise(x, z);
          std::vector<double> q(back.size()), p(size_t(K), 0.0);
          svm->PredictProbabilities(z, q.data());
          for (size_t j = 0; j < back.size(); ++j) p[size_t(back[j])] = q[j];
          return p;
        });
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string train, val, out, model, scan, ply, dump, compare;
  SegmentOptions so;
  VoxelizeOptions voxelize;  // --voxel: the voxel size of --scan.
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--train") train = argv[i + 1];
    else if (a == "--val") val = argv[i + 1];
    else if (a == "-o") out = argv[i + 1];
    else if (a == "--model") model = argv[i + 1];
    else if (a == "--scan") scan = argv[i + 1];
    else if (a == "--ply") ply = argv[i + 1];
    else if (a == "--dump") dump = argv[i + 1];
    else if (a == "--compare") compare = argv[i + 1];
    else if (a == "--wall-coverage") so.wall_min_coverage = std::atof(argv[i + 1]);
    else if (a == "--split-height") so.split_height_m = std::atof(argv[i + 1]);
    else if (a == "--split-step") so.split_top_step_m = std::atof(argv[i + 1]);
    else if (a == "--min-part") so.min_part_area_m2 = std::atof(argv[i + 1]);
    else if (a == "--wall-length") so.wall_min_length_m = std::atof(argv[i + 1]);
    else if (a == "--front-max") so.front_max_depth_m = std::atof(argv[i + 1]);
    else if (a == "--front-min") so.front_min_depth_m = std::atof(argv[i + 1]);
    else if (a == "--wall-dilation") so.wall_dilation_cells = std::atoi(argv[i + 1]);
    else if (a == "--voxel") voxelize.voxel_size_m = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "segments_bench: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  const LabelLevel level = SecondLevel();
  if (!compare.empty()) return Compare(compare, level);
  if (!train.empty()) {
    SegmentTrainingOptions o;
    o.segments = so;
    if (!ParseSeedList(train, "--train", &o.train_seeds).ok() || !ParseSeedList(val.empty() ? "100-109" : val, "--val", &o.val_seeds).ok()) return 2;
    if (dump.empty()) {
      SegmentTrainingSummary s;
      Result<SegmentClassifier> clf = TrainSegmentClassifier(o, &s);
      if (!clf.ok()) {
        std::fprintf(stderr, "segments_bench: %s\n", clf.status().message().c_str());
        return 1;
      }
      std::printf("%s%.1f s\n", s.ToText(level).c_str(), s.seconds);
      if (!out.empty() && !clf->SaveToDirectory(out).ok()) return 1;
    } else {  // Only the segments of the --train seeds, dumped (no training).  // The training segments: seed, class, voxels, features (tab-separated).
      FILE* f = std::fopen(dump.c_str(), "w");
      if (!f) return 1;
      for (uint64_t seed : o.train_seeds) {
        std::vector<float> features;
        std::vector<int> classes, voxels;
        if (!LabelledSegments(seed, o, &features, &classes, &voxels).ok()) return 1;
        for (size_t i = 0; i < classes.size(); ++i) {
          std::fprintf(f, "%llu\t%s\t%d", static_cast<unsigned long long>(seed), level.class_names[size_t(classes[i])].c_str(), voxels[i]);
          for (int k = 0; k < kNumSegmentFeatures; ++k) std::fprintf(f, "\t%.3f", features[i * kNumSegmentFeatures + size_t(k)]);
          std::fprintf(f, "\n");
        }
      }
      std::fclose(f);
    }
    if (model.empty()) model = out + "/" + SegmentClassifierFile(SegmentClassifierKind::kKnn);
  }
  if (!scan.empty()) {
    Result<SegmentClassifier> clf =
        SegmentClassifier::Load(model, model.ends_with(".forest") ? SegmentClassifierKind::kForest : SegmentClassifierKind::kKnn);
    if (!clf.ok()) {
      std::fprintf(stderr, "segments_bench: %s\n", clf.status().message().c_str());
      return 1;
    }
    Result<Scene> scene = LoadScene(scan, LoadOptions{});
    if (!scene.ok()) return 1;
    // The canonical frame as `semvox run` finds it; the --ply output goes back to the input frame.
    const SceneFrame frame = EstimateSceneFrame(*scene);
    const Eigen::Isometry3d input_from_world = frame.identity() ? Eigen::Isometry3d::Identity() : frame.input_from_canonical();
    if (!frame.identity()) TransformScene(frame.canonical_from_input, &*scene);
    Result<VoxelMap> map = Voxelize(*scene, voxelize);
    if (!map.ok()) return 1;
    const SegmentationResult seg = SegmentObjects(map->grid, map->floor_z, map->ceiling_z, map->ceiling_found, so);
    size_t structure[4] = {0, 0, 0, 0};
    for (uint8_t s : seg.structure) ++structure[s];
    std::printf("floor z %.3f, ceiling %s %.3f; structure voxels: floor %zu ceiling %zu wall %zu; %zu segments\n", map->floor_z,
                map->ceiling_found ? "found" : "not found", map->ceiling_z, structure[1], structure[2], structure[3], seg.segments.size());
    std::vector<int> label(map->grid.size(), 0), segment_of(map->grid.size(), -1);
    for (size_t i = 0; i < label.size(); ++i) {
      const int kStructure[4] = {0, 2, 22, 1};  // none, floor, ceiling, wall (NYU40)
      if (map->grid.state(i) == VoxelState::kOccupied) label[i] = seg.structure[i] ? kStructure[seg.structure[i]] : 40;
    }
    const std::vector<int> nyu40 = Nyu40OfClasses(level);
    for (const ObjectSegment& s : seg.segments) {
      const std::vector<double> p = clf->Probabilities({s.features.data(), s.features.size()});
      const int best = int(std::max_element(p.begin(), p.end()) - p.begin());
      for (uint32_t v : s.voxels) label[v] = nyu40[size_t(best)], segment_of[v] = int(&s - seg.segments.data());
      const auto c = map->grid.Cell(s.voxels[s.voxels.size() / 2]);
      const Eigen::Vector3d x = map->grid.CellCenter(c[0], c[1], c[2]);
      std::printf("%6zu voxels at (%.2f %.2f %.2f): %-16s %.2f", s.voxels.size(), x.x(), x.y(), x.z(), level.class_names[size_t(best)].c_str(), p[size_t(best)]);
      std::vector<size_t> order(p.size());
      std::iota(order.begin(), order.end(), size_t(0));
      std::partial_sort(order.begin(), order.begin() + 3, order.end(), [&](size_t a, size_t b) { return p[a] > p[b]; });
      std::printf(" (then %s %.2f, %s %.2f) |", level.class_names[order[1]].c_str(), p[order[1]], level.class_names[order[2]].c_str(), p[order[2]]);
      for (int f = 0; f < kNumSegmentFeatures; ++f) std::printf(" %s %.2f", SegmentFeatureName(f), s.features[size_t(f)]);
      std::printf("\n");
    }
    if (!dump.empty()) {  // The scan's segments: "scan", segment index, voxels, features (tab-separated).
      FILE* f = std::fopen(dump.c_str(), "w");
      if (!f) return 1;
      for (size_t i = 0; i < seg.segments.size(); ++i) {
        std::fprintf(f, "scan\t%zu\t%zu", i, seg.segments[i].voxels.size());
        for (int k = 0; k < kNumSegmentFeatures; ++k) std::fprintf(f, "\t%.3f", seg.segments[i].features[size_t(k)]);
        std::fprintf(f, "\n");
      }
      std::fclose(f);
    }
    if (!ply.empty()) {  // x y z label segment per occupied voxel (structure: wall / floor / ceiling; 40 unsegmented; segment -1)
      FILE* f = std::fopen(ply.c_str(), "w");
      size_t n = 0;
      for (int l : label) n += l > 0;
      std::fprintf(f, "ply\nformat ascii 1.0\nelement vertex %zu\nproperty float x\nproperty float y\nproperty float z\nproperty int label\nproperty int segment\nend_header\n", n);
      for (size_t i = 0; i < label.size(); ++i) {
        if (!label[i]) continue;
        const auto c = map->grid.Cell(i);
        const Eigen::Vector3d x = input_from_world * map->grid.CellCenter(c[0], c[1], c[2]);
        std::fprintf(f, "%.3f %.3f %.3f %d %d\n", x.x(), x.y(), x.z(), label[i], segment_of[i]);
      }
      std::fclose(f);
    }
  }
  return 0;
}
