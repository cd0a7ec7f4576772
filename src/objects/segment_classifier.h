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

  // Writes DIR/SegmentClassifierFile(kind()) atomically and removes the other kind's file from DIR, so that
  // the directory holds the model just trained and nothing that would be loaded instead.
  Status SaveToDirectory(const std::string& dir) const;
  // DIR/object_segments.forest when it exists, else DIR/object_segments.knn; nullopt when neither does.
  static Result<std::optional<SegmentClassifier>> LoadFromDirectory(const std::string& dir);
  static Result<SegmentClassifier> Load(const std::string& path, SegmentClassifierKind kind);

 private:
  std::unique_ptr<KnnClassifier> knn_;
  std::unique_ptr<RandomForest> forest_;
};

}  // namespace semvox
