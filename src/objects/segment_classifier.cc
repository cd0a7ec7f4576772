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

bool HighTopsToOtherClasses(double top_surface_m, std::span<const ClassTopLimit> limits, std::vector<double>* p) {
  if (p->empty() || !std::isfinite(top_surface_m)) return false;
  const double floor = *std::min_element(p->begin(), p->end());
  std::vector<char> excluded(p->size(), 0);
  for (const ClassTopLimit& l : limits)
    if (l.cls >= 0 && size_t(l.cls) < p->size() && top_surface_m > l.max_top_m) excluded[size_t(l.cls)] = 1;
  // Only a segment whose most probable class it cannot be: the small probabilities of the others stay as the
  // classifier gave them.
  if (!excluded[size_t(std::max_element(p->begin(), p->end()) - p->begin())]) return false;
  double moved = 0, kept = 0;
  for (size_t k = 0; k < p->size(); ++k) (excluded[k] ? moved : kept) += (*p)[k] - floor;
  if (!(moved > 0) || !(kept > 0)) return false;
  for (size_t k = 0; k < p->size(); ++k)
    (*p)[k] = excluded[k] ? floor : (*p)[k] + moved * ((*p)[k] - floor) / kept;
  return true;
}

std::vector<size_t> SofaBacksBesideSeats(const VoxelGrid& grid, const std::vector<ObjectSegment>& segments, int bed, int sofa,
                                         double min_seat_probability, double min_rise_m, std::vector<std::vector<double>>* p) {
  std::vector<size_t> changed;
  const size_t n = segments.size();
  if (p->size() != n || bed < 0 || sofa < 0 || bed == sofa) return changed;
  auto argmax = [&](size_t i) {
    const std::vector<double>& q = (*p)[i];
    return q.empty() ? -1 : int(std::max_element(q.begin(), q.end()) - q.begin());
  };
  std::vector<int> best(n);
  for (size_t i = 0; i < n; ++i) best[i] = argmax(i);
  // Most scans hold no bed-called segment or no sure seat: no voxel index is needed then.
  bool any_bed = false, any_seat = false;
  for (size_t i = 0; i < n; ++i) {
    any_bed |= best[i] == bed;
    any_seat |= best[i] == sofa && (*p)[i][size_t(sofa)] >= min_seat_probability;
  }
  if (!any_bed || !any_seat) return changed;
  std::vector<int32_t> segment_of(grid.size(), -1);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t v : segments[i].voxels) segment_of[v] = int32_t(i);
  for (size_t i = 0; i < n; ++i) {
    if (best[i] != bed || size_t(std::max(bed, sofa)) >= (*p)[i].size()) continue;
    const float top = segments[i].features[kSegTopSurface];
    bool beside_seat = false;
    for (size_t k = 0; k < segments[i].voxels.size() && !beside_seat; ++k) {
      const std::array<int, 3> c = grid.Cell(segments[i].voxels[k]);
      for (int dz = -1; dz <= 1 && !beside_seat; ++dz)
        for (int dy = -1; dy <= 1 && !beside_seat; ++dy)
          for (int dx = -1; dx <= 1 && !beside_seat; ++dx) {
            if (!grid.Contains(c[0] + dx, c[1] + dy, c[2] + dz)) continue;
            const int32_t j = segment_of[grid.Index(c[0] + dx, c[1] + dy, c[2] + dz)];
            if (j < 0 || size_t(j) == i || best[size_t(j)] != sofa) continue;
            beside_seat = (*p)[size_t(j)][size_t(sofa)] >= min_seat_probability &&
                          top > segments[size_t(j)].features[kSegTopSurface] + min_rise_m;
          }
    }
    if (beside_seat && MoveProbability(size_t(bed), size_t(sofa), &(*p)[i])) changed.push_back(i);
  }
  return changed;
}

}  // namespace semvox
