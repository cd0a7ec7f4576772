// The object-segment classifier (object_segments.h) as `semvox run` loads it: a k-NN over the 18 shape
// features (Eq. 4 of the MST-CRF paper; the shipped model, models/object_segments.knn) or a random forest
// (random_forest.h; models/object_segments.forest). Both give second-level class probabilities that sum to
// one and never reach 0, which the Voxel-CRF turns into its segment term.
//
//   Result<SegmentClassifier> clf = SegmentClassifier::LoadFromDirectory("models");  // .forest, else .knn
//   std::vector<double> p = clf->Probabilities(segment.features);
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"
#include "objects/object_segments.h"

namespace semvox {

class KnnClassifier;
class RandomForest;

enum class SegmentClassifierKind { kKnn, kForest };

// "knn" / "forest" (both directions); false for any other name.
const char* SegmentClassifierKindName(SegmentClassifierKind kind);
bool ParseSegmentClassifierKind(const std::string& name, SegmentClassifierKind* kind);
// The model's file name in a models directory: object_segments.knn or object_segments.forest.
std::string SegmentClassifierFile(SegmentClassifierKind kind);

class SegmentClassifier {
 public:
  explicit SegmentClassifier(KnnClassifier knn);
  explicit SegmentClassifier(RandomForest forest);
  SegmentClassifier(SegmentClassifier&&) noexcept;
  SegmentClassifier& operator=(SegmentClassifier&&) noexcept;
  ~SegmentClassifier();

  SegmentClassifierKind kind() const;
  int dims() const;
  int num_classes() const;
  std::vector<double> Probabilities(std::span<const float> features) const;
  // How unlike every training segment a segment is (k-NN only): its mean distance to the k nearest training
  // segments (standardised features) over the 0.99-quantile of the training segments' own distances to their
  // k nearest others. Above 1 it is farther from the training shapes than 99 % of the training segments are
  // from the rest, and its class is a guess. NaN for the forest, which keeps no training rows.
  double Unfamiliarity(std::span<const float> features) const;
  // Probabilities and Unfamiliarity from one search.
  std::vector<double> Probabilities(std::span<const float> features, double* unfamiliarity) const;
  // The denominator above (0.99-quantile of the training segments' neighbour distances); NaN for the forest.
  double familiar_distance() const { return familiar_distance_; }

  // Writes DIR/SegmentClassifierFile(kind()) atomically and removes the other kind's file from DIR, so that
  // the directory holds the model just trained and nothing that would be loaded instead.
  Status SaveToDirectory(const std::string& dir) const;
  // DIR/object_segments.forest when it exists, else DIR/object_segments.knn; nullopt when neither does.
  static Result<std::optional<SegmentClassifier>> LoadFromDirectory(const std::string& dir);
  static Result<SegmentClassifier> Load(const std::string& path, SegmentClassifierKind kind);

 private:
  std::unique_ptr<KnnClassifier> knn_;
  std::unique_ptr<RandomForest> forest_;
  double familiar_distance_;
};

// A counter is a work surface at counter height (kitchen counters 0.85-0.95 m, bathroom vanities from about
// 0.76 m; the generator's 0.87-0.93 m). The shape classifier still calls counter what is counter-like by its
// other features and lower (on the ScanNet studio a desk at 0.72 m and a low table at 0.47 m, both standing
// against something that rises above them, as counters stand below wall cabinets): a segment whose top surface
// (kSegTopSurface, metres above the floor) lies below `min_top_m` is no counter, and `p[counter]` moves to
// `p[table]` (a flat top at table height), down to the smallest probability in `p` (the classifier's floor), so
// that `p` keeps its sum. Returns whether anything moved (false when the segment is high enough, `counter` or
// `table` is out of range, or `min_top_m` <= 0).
bool LowCounterToTable(double top_surface_m, int counter, int table, double min_top_m, std::vector<double>* p);

}  // namespace semvox
