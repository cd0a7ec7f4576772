#include "objects/segment_classifier.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "objects/random_forest.h"
#include "perception/knn_unary.h"

namespace semvox {

namespace fs = std::filesystem;

const char* SegmentClassifierKindName(SegmentClassifierKind kind) { return kind == SegmentClassifierKind::kForest ? "forest" : "knn"; }

bool ParseSegmentClassifierKind(const std::string& name, SegmentClassifierKind* kind) {
  if (name == "knn") *kind = SegmentClassifierKind::kKnn;
  else if (name == "forest") *kind = SegmentClassifierKind::kForest;
  else return false;
  return true;
}

std::string SegmentClassifierFile(SegmentClassifierKind kind) { return std::string("object_segments.") + SegmentClassifierKindName(kind); }

SegmentClassifier::SegmentClassifier(KnnClassifier knn)
    : knn_(std::make_unique<KnnClassifier>(std::move(knn))),
      familiar_distance_(knn_->TrainingNeighbourDistanceQuantile(KnnClassifier::kFamiliarQuantile)) {}
SegmentClassifier::SegmentClassifier(RandomForest forest)
    : forest_(std::make_unique<RandomForest>(std::move(forest))), familiar_distance_(std::numeric_limits<double>::quiet_NaN()) {}
SegmentClassifier::SegmentClassifier(SegmentClassifier&&) noexcept = default;
SegmentClassifier& SegmentClassifier::operator=(SegmentClassifier&&) noexcept = default;
SegmentClassifier::~SegmentClassifier() = default;

SegmentClassifierKind SegmentClassifier::kind() const { return forest_ ? SegmentClassifierKind::kForest : SegmentClassifierKind::kKnn; }
int SegmentClassifier::dims() const { return forest_ ? forest_->dims() : knn_->dims(); }
int SegmentClassifier::num_classes() const { return forest_ ? forest_->num_classes() : knn_->num_classes(); }

std::vector<double> SegmentClassifier::Probabilities(std::span<const float> features) const {
  return forest_ ? forest_->Probabilities(features) : knn_->Probabilities(features);
}

double SegmentClassifier::Unfamiliarity(std::span<const float> features) const {
  double unfamiliarity = 0;
  Probabilities(features, &unfamiliarity);
  return unfamiliarity;
}

std::vector<double> SegmentClassifier::Probabilities(std::span<const float> features, double* unfamiliarity) const {
  *unfamiliarity = std::numeric_limits<double>::quiet_NaN();
  if (forest_) return forest_->Probabilities(features);
  double distance = 0;
  std::vector<double> p = knn_->Probabilities(features, &distance);
  if (familiar_distance_ > 0) *unfamiliarity = distance / familiar_distance_;
  return p;
}

Status SegmentClassifier::SaveToDirectory(const std::string& dir) const {
  const SegmentClassifierKind other = kind() == SegmentClassifierKind::kForest ? SegmentClassifierKind::kKnn : SegmentClassifierKind::kForest;
  const std::string path = dir + "/" + SegmentClassifierFile(kind());
  SEMVOX_RETURN_IF_ERROR(forest_ ? forest_->Save(path) : knn_->Save(path));
  std::error_code ec;
  fs::remove(dir + "/" + SegmentClassifierFile(other), ec);
  if (ec) return Status::InvalidInput(FileError(dir + "/" + SegmentClassifierFile(other), "cannot remove the other segment model: " + ec.message()));
  return Status::Ok();
}

Result<SegmentClassifier> SegmentClassifier::Load(const std::string& path, SegmentClassifierKind kind) {
  if (kind == SegmentClassifierKind::kForest) {
    Result<RandomForest> rf = RandomForest::Load(path);
    if (!rf.ok()) return rf.status();
    return SegmentClassifier(std::move(rf).value());
  }
  Result<KnnClassifier> knn = KnnClassifier::Load(path);
  if (!knn.ok()) return knn.status();
  return SegmentClassifier(std::move(knn).value());
}

Result<std::optional<SegmentClassifier>> SegmentClassifier::LoadFromDirectory(const std::string& dir) {
  for (SegmentClassifierKind kind : {SegmentClassifierKind::kForest, SegmentClassifierKind::kKnn}) {
    const std::string path = dir + "/" + SegmentClassifierFile(kind);
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    Result<SegmentClassifier> clf = Load(path, kind);
    if (!clf.ok()) return clf.status();
    return std::optional<SegmentClassifier>(std::move(clf).value());
  }
  return std::optional<SegmentClassifier>();
}

namespace {

// Moves p[from] to p[to], down to the smallest probability in p (the classifier's floor), so that p keeps its
// sum; false when p[from] is at the floor already. `from` and `to` are valid, different indices.
bool MoveProbability(size_t from, size_t to, std::vector<double>* p) {
  const double floor = *std::min_element(p->begin(), p->end());
  if ((*p)[from] <= floor) return false;
  (*p)[to] += (*p)[from] - floor;
  (*p)[from] = floor;
  return true;
}

}  // namespace

bool LowCounterToTable(double top_surface_m, int counter, int table, double min_top_m, std::vector<double>* p) {
  const int k = int(p->size());
  if (min_top_m <= 0 || !(top_surface_m < min_top_m) || counter < 0 || table < 0 || counter >= k || table >= k || counter == table)
    return false;
  return MoveProbability(size_t(counter), size_t(table), p);
}

}  // namespace semvox
