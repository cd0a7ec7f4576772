#include "objects/other_labels.h"

#include <algorithm>

#include "core/labels.h"
#include "perception/knn_unary.h"
#include "perception/label_levels.h"

namespace semvox {

OtherFeatureVector OtherFeatures(const VoxelGrid& grid, const SegmentationResult& segments, const ObjectSegment& segment,
                                 const std::vector<uint32_t>& other) {
  OtherFeatureVector f{};
  const std::array<float, kNumSegmentFeatures> own = DescribeVoxels(grid, other, segments);
  std::copy(own.begin(), own.end(), f.begin());
  f[kSegNeighbourRise] = std::max(0.0f, segment.features[kSegTop] - own[kSegTop]);
  f[kOtherShare] = segment.voxels.empty() ? 0.0f : float(double(other.size()) / double(segment.voxels.size()));
  f[kOtherSupportTop] = segment.features[kSegTopSurface];
  f[kOtherSegmentFootprint] = segment.features[kSegFootprint];
  return f;
}

bool IsOtherNyu40(int id) {
  static const std::vector<uint8_t> other = [] {
    const LabelLevel level = SecondLevel();
    int other_class = -1;
    for (int k = 0; k < level.num_classes(); ++k)
      if (level.class_names[size_t(k)] == "other") other_class = k;
    std::vector<uint8_t> o(size_t(kNumNyu40), 0);
    for (int i = 1; i < kNumNyu40; ++i) o[size_t(i)] = level.class_of_nyu40[size_t(i)] == other_class;
    return o;
  }();
  return id > 0 && id < kNumNyu40 && other[size_t(id)];
}

OtherLabeller::OtherLabeller(KnnClassifier knn) : knn_(std::make_unique<KnnClassifier>(std::move(knn))) {}
OtherLabeller::OtherLabeller(OtherLabeller&&) noexcept = default;
OtherLabeller& OtherLabeller::operator=(OtherLabeller&&) noexcept = default;
OtherLabeller::~OtherLabeller() = default;

int OtherLabeller::Label(std::span<const float> features) const {
  const std::vector<int> p = knn_->NeighbourCounts(features);
  int best = nyu40::kOtherProp;
  for (int id = 1; id < int(p.size()); ++id)
    if (IsOtherNyu40(id) && p[size_t(id)] > p[size_t(best)]) best = id;
  return best;
}

Status OtherLabeller::Save(const std::string& path) const { return knn_->Save(path); }

namespace {

// A k-NN over kNumOtherFeatures with kNumNyu40 classes, or one line naming the file.
Result<KnnClassifier> LoadFineKnn(const std::string& path, const char* what) {
  Result<KnnClassifier> knn = KnnClassifier::Load(path);
  if (!knn.ok()) return knn.status();
  if (knn->dims() != kNumOtherFeatures || knn->num_classes() != kNumNyu40)
    return Status::InvalidInput(FileError(path, std::string("not a model of ") + what + " (" + std::to_string(knn->dims()) + " features, " +
                                                    std::to_string(knn->num_classes()) + " classes; expected " +
                                                    std::to_string(int(kNumOtherFeatures)) + " and " + std::to_string(kNumNyu40) + ")",
                                          "re-run `semvox train --segments`"));
  return knn;
}

}  // namespace

Result<OtherLabeller> OtherLabeller::Load(const std::string& path) {
  Result<KnnClassifier> knn = LoadFineKnn(path, "the other class's labels");
  if (!knn.ok()) return knn.status();
  return OtherLabeller(std::move(knn).value());
}

std::vector<std::vector<uint32_t>> ItemsOnTop(const VoxelGrid& grid, const SegmentationResult& segments, const ObjectSegment& segment,
                                              int min_voxels) {
  std::vector<std::vector<uint32_t>> groups;
  if (segment.voxels.empty()) return groups;
  const int top_cell = grid.CellOf(Eigen::Vector3d(0, 0, segments.floor_z + segment.features[kSegTopSurface]))[2];
  std::vector<uint32_t> upper;  // Ascending, as the segment's voxels are.
  for (uint32_t v : segment.voxels)
    if (grid.Cell(v)[2] > top_cell) upper.push_back(v);
  std::vector<uint8_t> taken(upper.size(), 0);
  auto find = [&](int x, int y, int z) -> int {
    if (!grid.Contains(x, y, z)) return -1;
    const uint32_t v = uint32_t(grid.Index(x, y, z));
    const auto it = std::lower_bound(upper.begin(), upper.end(), v);
    return it != upper.end() && *it == v ? int(it - upper.begin()) : -1;
  };
  for (size_t s = 0; s < upper.size(); ++s) {
    if (taken[s]) continue;
    std::vector<uint32_t> group{upper[s]};
    taken[s] = 1;
    for (size_t head = 0; head < group.size(); ++head) {
      const auto c = grid.Cell(group[head]);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int i = find(c[0] + dx, c[1] + dy, c[2] + dz);
            if (i >= 0 && !taken[size_t(i)]) taken[size_t(i)] = 1, group.push_back(upper[size_t(i)]);
          }
    }
    if (int(group.size()) < min_voxels) continue;
    std::sort(group.begin(), group.end());
    groups.push_back(std::move(group));
  }
  return groups;
}

ItemLabeller::ItemLabeller(KnnClassifier knn)
    : knn_(std::make_unique<KnnClassifier>(std::move(knn))),
      familiar_distance_(knn_->TrainingNeighbourDistanceQuantile(KnnClassifier::kFamiliarQuantile)) {}
ItemLabeller::ItemLabeller(ItemLabeller&&) noexcept = default;
ItemLabeller& ItemLabeller::operator=(ItemLabeller&&) noexcept = default;
ItemLabeller::~ItemLabeller() = default;

int ItemLabeller::Label(std::span<const float> features) const {
  double distance = 0;
  const std::vector<int> counts = knn_->NeighbourCountsAndDistance(features, &distance);
  if (!(distance <= familiar_distance_)) return 0;
  int best = 0;
  for (int id = 1; id < int(counts.size()); ++id)
    if (counts[size_t(id)] > counts[size_t(best)]) best = id;
  return best;
}

Status ItemLabeller::Save(const std::string& path) const { return knn_->Save(path); }

Result<ItemLabeller> ItemLabeller::Load(const std::string& path) {
  Result<KnnClassifier> knn = LoadFineKnn(path, "the items on top of segments");
  if (!knn.ok()) return knn.status();
  return ItemLabeller(std::move(knn).value());
}

}  // namespace semvox
