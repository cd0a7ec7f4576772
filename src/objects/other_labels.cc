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
  const std::vector<double> p = knn_->Probabilities(features);
  int best = nyu40::kOtherProp;
  for (int id = 1; id < int(p.size()); ++id)
    if (IsOtherNyu40(id) && p[size_t(id)] > p[size_t(best)]) best = id;
  return best;
}

Status OtherLabeller::Save(const std::string& path) const { return knn_->Save(path); }

Result<OtherLabeller> OtherLabeller::Load(const std::string& path) {
  Result<KnnClassifier> knn = KnnClassifier::Load(path);
  if (!knn.ok()) return knn.status();
  if (knn->dims() != kNumOtherFeatures || knn->num_classes() != kNumNyu40)
    return Status::InvalidInput(FileError(path, "not a model of the other class's labels (" + std::to_string(knn->dims()) + " features, " +
                                                    std::to_string(knn->num_classes()) + " classes; expected " +
                                                    std::to_string(int(kNumOtherFeatures)) + " and " + std::to_string(kNumNyu40) + ")",
                                          "re-run `semvox train --segments`"));
  return OtherLabeller(std::move(knn).value());
}

}  // namespace semvox
