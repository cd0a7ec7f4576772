// Object segments classified by shape (objects/object_segments.h): trains the k-NN on generated apartments
// and/or classifies the segments of a scan, printing each segment with its shape and class.
//
//   segments_bench --train 0-39 --val 100-109 [-o MODEL.knn] [--dump SEGMENTS.tsv]
//   segments_bench --model MODEL.knn --scan INPUT [--up z]      # segments of a real scan
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "apps/commands.h"
#include "apps/semantic_stage.h"
#include "io/load_scene.h"
#include "mapping/voxelizer.h"
#include "objects/segment_training.h"

using namespace semvox;

int main(int argc, char** argv) {
  std::string train, val, out, model, scan, ply, dump;
  SegmentOptions so;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--train") train = argv[i + 1];
    else if (a == "--val") val = argv[i + 1];
    else if (a == "-o") out = argv[i + 1];
    else if (a == "--model") model = argv[i + 1];
    else if (a == "--scan") scan = argv[i + 1];
    else if (a == "--ply") ply = argv[i + 1];
    else if (a == "--dump") dump = argv[i + 1];
    else if (a == "--wall-coverage") so.wall_min_coverage = std::atof(argv[i + 1]);
    else if (a == "--split-height") so.split_height_m = std::atof(argv[i + 1]);
    else if (a == "--split-step") so.split_top_step_m = std::atof(argv[i + 1]);
    else if (a == "--min-part") so.min_part_area_m2 = std::atof(argv[i + 1]);
    else if (a == "--wall-length") so.wall_min_length_m = std::atof(argv[i + 1]);
    else if (a == "--front-max") so.front_max_depth_m = std::atof(argv[i + 1]);
    else if (a == "--front-min") so.front_min_depth_m = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "segments_bench: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  const LabelLevel level = SecondLevel();
  if (!train.empty()) {
    SegmentTrainingOptions o;
    if (!ParseSeedList(train, "--train", &o.train_seeds).ok() || !ParseSeedList(val.empty() ? "100-109" : val, "--val", &o.val_seeds).ok()) return 2;
    SegmentTrainingSummary s;
    Result<KnnClassifier> clf = TrainSegmentClassifier(o, &s);
    if (!clf.ok()) {
      std::fprintf(stderr, "segments_bench: %s\n", clf.status().message().c_str());
      return 1;
    }
    std::printf("%s%.1f s\n", s.ToText(level).c_str(), s.seconds);
    if (!out.empty() && !clf->Save(out).ok()) return 1;
    if (!dump.empty()) {  // The training segments: seed, class, voxels, features (tab-separated).
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
    if (model.empty()) model = out;
  }
  if (!scan.empty()) {
    Result<KnnClassifier> clf = KnnClassifier::Load(model);
    if (!clf.ok()) {
      std::fprintf(stderr, "segments_bench: %s\n", clf.status().message().c_str());
      return 1;
    }
    Result<Scene> scene = LoadScene(scan, LoadOptions{});
    if (!scene.ok()) return 1;
    Result<VoxelMap> map = Voxelize(*scene, VoxelizeOptions{});
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
      std::printf("%6zu voxels at (%.2f %.2f %.2f): %-16s %.2f |", s.voxels.size(), x.x(), x.y(), x.z(), level.class_names[size_t(best)].c_str(), p[size_t(best)]);
      for (int f = 0; f < kNumSegmentFeatures; ++f) std::printf(" %s %.2f", SegmentFeatureName(f), s.features[size_t(f)]);
      std::printf("\n");
    }
    if (!ply.empty()) {  // x y z label segment per occupied voxel (structure: wall / floor / ceiling; 40 unsegmented; segment -1)
      FILE* f = std::fopen(ply.c_str(), "w");
      size_t n = 0;
      for (int l : label) n += l > 0;
      std::fprintf(f, "ply\nformat ascii 1.0\nelement vertex %zu\nproperty float x\nproperty float y\nproperty float z\nproperty int label\nproperty int segment\nend_header\n", n);
      for (size_t i = 0; i < label.size(); ++i) {
        if (!label[i]) continue;
        const auto c = map->grid.Cell(i);
        const Eigen::Vector3d x = map->grid.CellCenter(c[0], c[1], c[2]);
        std::fprintf(f, "%.3f %.3f %.3f %d %d\n", x.x(), x.y(), x.z(), label[i], segment_of[i]);
      }
      std::fclose(f);
    }
  }
  return 0;
}
