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

// What stands how high: a segment whose most probable class cannot stand that high gives the probability of
// every class it exceeds to the others, in proportion; within the limits, or with a plausible most probable
// class, nothing moves.
TEST(SegmentClassifier, HighTopGivesItsClassesProbabilityToTheOthers) {
  const int table = 1, chair = 2, cabinet = 3;
  const std::vector<ClassTopLimit> limits = {{table, 1.4}, {chair, 1.2}, {7, 1.0}, {-1, 1.0}};  // Out of range: ignored.
  const std::vector<double> p0 = {0.01, 0.5, 0.29, 0.2};
  std::vector<double> p = p0;
  EXPECT_TRUE(HighTopsToOtherClasses(2.3, limits, &p));  // A wardrobe's top.
  EXPECT_DOUBLE_EQ(p[table], 0.01);
  EXPECT_DOUBLE_EQ(p[chair], 0.01);
  const double moved = 0.49 + 0.28, kept = 0.0 + 0.19;  // Above the floor (0.01).
  EXPECT_NEAR(p[cabinet], 0.2 + moved * 0.19 / kept, 1e-12);
  EXPECT_NEAR(p[0], 0.01, 1e-12);  // At the floor: gets nothing.
  EXPECT_NEAR(p[0] + p[1] + p[2] + p[3], 1.0, 1e-12);
  p = {0.01, 0.29, 0.5, 0.2};  // A chair over the chair's limit, not the table's: only the chair goes.
  EXPECT_TRUE(HighTopsToOtherClasses(1.3, limits, &p));
  EXPECT_DOUBLE_EQ(p[chair], 0.01);
  EXPECT_NEAR(p[table], 0.29 + 0.49 * 0.28 / (0.28 + 0.19), 1e-12);
  EXPECT_NEAR(p[cabinet], 0.2 + 0.49 * 0.19 / (0.28 + 0.19), 1e-12);
  EXPECT_NEAR(p[0] + p[1] + p[2] + p[3], 1.0, 1e-12);
  for (double top : {0.72, 1.2, 1.4}) {  // Within the table's limit (a bar table at 1.1 m).
    p = p0;
    EXPECT_FALSE(HighTopsToOtherClasses(top, limits, &p)) << top;
    EXPECT_EQ(p, p0);
  }
  p = {0.01, 0.2, 0.09, 0.7};  // The most probable class (cabinet) has no limit: the rest stays as given.
  const std::vector<double> p1 = p;
  EXPECT_FALSE(HighTopsToOtherClasses(2.3, limits, &p));
  EXPECT_EQ(p, p1);
  p = p0;
  EXPECT_FALSE(HighTopsToOtherClasses(std::nan(""), limits, &p));
  EXPECT_EQ(p, p0);
  p = {0.01, 0.6, 0.38, 0.01};  // Every class above the floor excluded: nowhere to move.
  EXPECT_FALSE(HighTopsToOtherClasses(2.3, limits, &p));
}

// A sofa's back beside its seat: the back (called bed) touching a sure seat and standing higher becomes sofa; a bed
// beside a sofa at its own height, a bed beside an unsure seat, or a bed apart from the seat stays bed.
TEST(SegmentClassifier, SofaBackBesideItsSeatIsSofa) {
  VoxelGrid grid(0.05, {32768, 32768, 32768}, {40, 20, 20});
  auto block = [&](int x0, int x1, int z0, int z1, float top) {
    ObjectSegment s;
    for (int z = z0; z <= z1; ++z)
      for (int y = 5; y <= 10; ++y)
        for (int x = x0; x <= x1; ++x) s.voxels.push_back(uint32_t(grid.Index(x, y, z)));
    std::sort(s.voxels.begin(), s.voxels.end());
    s.features[kSegTopSurface] = top;
    return s;
  };
  const int bed = 1, sofa = 2;
  const std::vector<double> seat_p = {0.01, 0.01, 0.95, 0.03}, back_p = {0.01, 0.6, 0.3, 0.09};
  // Seat at x 0-9 (top 0.45 m), back at x 10-14 (top 0.75 m, touching), a bed at x 30-39 (apart).
  const std::vector<ObjectSegment> segs = {block(0, 9, 0, 8, 0.45f), block(10, 14, 0, 14, 0.75f), block(30, 39, 0, 10, 0.55f)};
  std::vector<std::vector<double>> p = {seat_p, back_p, back_p};
  EXPECT_EQ(SofaBacksBesideSeats(grid, segs, bed, sofa, 0.9, 0.15, &p), std::vector<size_t>{1});
  EXPECT_DOUBLE_EQ(p[1][sofa], 0.3 + 0.6 - 0.01);
  EXPECT_DOUBLE_EQ(p[1][bed], 0.01);
  EXPECT_NEAR(p[1][0] + p[1][1] + p[1][2] + p[1][3], 1.0, 1e-12);
  EXPECT_EQ(p[0], seat_p);
  EXPECT_EQ(p[2], back_p);  // Apart from the seat.
  p = {{0.01, 0.01, 0.8, 0.18}, back_p, back_p};  // An unsure seat.
  EXPECT_TRUE(SofaBacksBesideSeats(grid, segs, bed, sofa, 0.9, 0.15, &p).empty());
  std::vector<ObjectSegment> level = segs;
  level[1].features[kSegTopSurface] = 0.55f;  // A bed beside a sofa, 0.1 m higher than its seat.
  p = {seat_p, back_p, back_p};
  EXPECT_TRUE(SofaBacksBesideSeats(grid, level, bed, sofa, 0.9, 0.15, &p).empty());
  EXPECT_EQ(p[1], back_p);
}

}  // namespace
}  // namespace semvox
