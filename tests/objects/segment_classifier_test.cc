#include "objects/segment_classifier.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "objects/random_forest.h"
#include "core/file_util.h"
#include "perception/knn_unary.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// Two classes on one feature: x < 0.5 is class 0.
std::vector<float> X() { return {0.1f, 0.2f, 0.3f, 0.7f, 0.8f, 0.9f}; }
std::vector<int> Y() { return {0, 0, 0, 1, 1, 1}; }

SegmentClassifier Knn() {
  KnnOptions o;
  o.k = 3;
  return SegmentClassifier(KnnClassifier::Train(X(), 1, Y(), 2, o).value());
}
SegmentClassifier Forest() {
  RandomForestOptions o;
  o.trees = 5;
  o.features_per_split = 1;
  return SegmentClassifier(RandomForest::Train(X(), 1, Y(), 2, o).value());
}

TEST(SegmentClassifier, BothKindsClassifyAndSaveUnderTheirOwnName) {
  for (const SegmentClassifier& clf : {Knn(), Forest()}) {
    const float lo = 0.15f, hi = 0.85f;
    EXPECT_GT(clf.Probabilities({&lo, 1})[0], 0.9);
    EXPECT_GT(clf.Probabilities({&hi, 1})[1], 0.9);
    EXPECT_EQ(clf.dims(), 1);
    EXPECT_EQ(clf.num_classes(), 2);
  }
  EXPECT_EQ(SegmentClassifierFile(SegmentClassifierKind::kKnn), "object_segments.knn");
  EXPECT_EQ(SegmentClassifierFile(SegmentClassifierKind::kForest), "object_segments.forest");
  SegmentClassifierKind kind;
  EXPECT_TRUE(ParseSegmentClassifierKind("forest", &kind));
  EXPECT_EQ(kind, SegmentClassifierKind::kForest);
  EXPECT_FALSE(ParseSegmentClassifierKind("svm", &kind));
}

// Unfamiliarity: a segment among the training ones is familiar (under 1), one far from all of them is not;
// the forest keeps no rows and cannot tell (NaN). The k-NN loaded from disk tells the same.
TEST(SegmentClassifier, UnfamiliarityIsAboveOneFarFromEveryTrainingSegment) {
  const SegmentClassifier knn = Knn();
  EXPECT_GT(knn.familiar_distance(), 0.0);
  const float among = 0.25f, far = 5.0f;
  EXPECT_LT(knn.Unfamiliarity({&among, 1}), 1.0);
  EXPECT_GT(knn.Unfamiliarity({&far, 1}), 10.0);
  EXPECT_TRUE(std::isnan(Forest().Unfamiliarity({&far, 1})));
  EXPECT_TRUE(std::isnan(Forest().familiar_distance()));
  testing::ScratchDir dir("segment_unfamiliarity");
  ASSERT_TRUE(knn.SaveToDirectory(dir.File("")).ok());
  Result<std::optional<SegmentClassifier>> loaded = SegmentClassifier::LoadFromDirectory(dir.File(""));
  ASSERT_TRUE(loaded.ok() && loaded->has_value());
  EXPECT_DOUBLE_EQ((*loaded)->Unfamiliarity({&far, 1}), knn.Unfamiliarity({&far, 1}));
}

TEST(SegmentClassifier, ADirectoryHoldsOnlyTheModelLastSavedAndLoadsIt) {
  testing::ScratchDir dir("segment_classifier");
  const std::string d = dir.File("");
  Result<std::optional<SegmentClassifier>> none = SegmentClassifier::LoadFromDirectory(d);
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->has_value());

  ASSERT_TRUE(Forest().SaveToDirectory(d).ok());
  EXPECT_TRUE(std::filesystem::exists(d + "/object_segments.forest"));
  ASSERT_TRUE(Knn().SaveToDirectory(d).ok());  // Replaces the forest: the run must use what was trained last.
  EXPECT_FALSE(std::filesystem::exists(d + "/object_segments.forest"));
  Result<std::optional<SegmentClassifier>> knn = SegmentClassifier::LoadFromDirectory(d);
  ASSERT_TRUE(knn.ok() && knn->has_value());
  EXPECT_EQ((*knn)->kind(), SegmentClassifierKind::kKnn);

  ASSERT_TRUE(Forest().SaveToDirectory(d).ok());
  EXPECT_FALSE(std::filesystem::exists(d + "/object_segments.knn"));
  Result<std::optional<SegmentClassifier>> forest = SegmentClassifier::LoadFromDirectory(d);
  ASSERT_TRUE(forest.ok() && forest->has_value());
  EXPECT_EQ((*forest)->kind(), SegmentClassifierKind::kForest);

  // A broken model is an error naming the file, not a silent fallback to no segment term.
  ASSERT_TRUE(WriteFileAtomic(d + "/object_segments.forest", "semvox_random_forest 1\n1 2 1 0.001\ntree 1\nX\n").ok());
  Result<std::optional<SegmentClassifier>> bad = SegmentClassifier::LoadFromDirectory(d);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("object_segments.forest"), std::string::npos);
}

// A counter is a work surface at counter height: below the threshold the counter's probability goes to table,
// down to the classifier's floor (the smallest probability), and the sum stays one; at or above it, with the
// check off, or with a class out of range nothing moves.
TEST(SegmentClassifier, LowCounterGivesItsProbabilityToTable) {
  const int counter = 1, table = 2;
  const std::vector<double> p0 = {0.001, 0.7, 0.1, 0.199};
  std::vector<double> p = p0;
  EXPECT_TRUE(LowCounterToTable(0.47, counter, table, 0.75, &p));  // A coffee table's top.
  EXPECT_DOUBLE_EQ(p[counter], 0.001);
  EXPECT_DOUBLE_EQ(p[table], 0.1 + 0.699);
  EXPECT_DOUBLE_EQ(p[0], 0.001);
  EXPECT_DOUBLE_EQ(p[3], 0.199);
  EXPECT_NEAR(p[0] + p[1] + p[2] + p[3], 1.0, 1e-12);
  for (double top : {0.75, 0.9, 1.12}) {  // At counter height and above (a bar counter): a counter may stay.
    p = p0;
    EXPECT_FALSE(LowCounterToTable(top, counter, table, 0.75, &p)) << top;
    EXPECT_EQ(p, p0);
  }
  p = p0;
  EXPECT_FALSE(LowCounterToTable(0.47, counter, table, 0.0, &p));  // Off.
  EXPECT_FALSE(LowCounterToTable(std::nan(""), counter, table, 0.75, &p));
  EXPECT_FALSE(LowCounterToTable(0.47, -1, table, 0.75, &p));
  EXPECT_FALSE(LowCounterToTable(0.47, counter, 4, 0.75, &p));
  EXPECT_FALSE(LowCounterToTable(0.47, counter, counter, 0.75, &p));
  EXPECT_EQ(p, p0);
  p = {0.001, 0.001, 0.5, 0.498};  // Nothing above the floor to move.
  EXPECT_FALSE(LowCounterToTable(0.47, counter, table, 0.75, &p));
}

}  // namespace
}  // namespace semvox
