#include "perception/knn_unary.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>

namespace semvox {
namespace {

TEST(ClassFrequencyNormalisedProbability, Eq4OnAHandComputedCase) {
  // k = 10 neighbours: 6 of class 0, 3 of class 1, 1 of class 2; training set F = (50, 30, 20), N = 100.
  // r0 = 6/4 * 50/50 = 3/2, r1 = 3/7 * 70/30 = 1, r2 = 1/9 * 80/20 = 4/9; sum = 53/18.
  // P = (27/53, 18/53, 8/53).
  const std::vector<int> f = {6, 3, 1};
  const std::vector<int64_t> F = {50, 30, 20};
  const std::vector<double> p = ClassFrequencyNormalisedProbability(f, F);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_NEAR(p[0], 27.0 / 53.0, 1e-12);
  EXPECT_NEAR(p[1], 18.0 / 53.0, 1e-12);
  EXPECT_NEAR(p[2], 8.0 / 53.0, 1e-12);
}

TEST(ClassFrequencyNormalisedProbability, RareClassesGainOverRawVoteShares) {
  // Equal votes, but class 1 is rare in training: it must come out ahead.
  const std::vector<double> p = ClassFrequencyNormalisedProbability(std::vector<int>{5, 5}, std::vector<int64_t>{90, 10});
  EXPECT_GT(p[1], p[0]);
  EXPECT_NEAR(p[0] + p[1], 1.0, 1e-12);
}

TEST(ClassFrequencyNormalisedProbability, LimitsTheEquationLeavesOpen) {
  // Unanimous neighbours: that class gets everything.
  std::vector<double> p = ClassFrequencyNormalisedProbability(std::vector<int>{0, 10, 0}, std::vector<int64_t>{5, 5, 5});
  EXPECT_EQ(p, (std::vector<double>{0, 1, 0}));
  // No neighbours: uniform over the classes seen in training.
  p = ClassFrequencyNormalisedProbability(std::vector<int>{0, 0, 0}, std::vector<int64_t>{5, 0, 5});
  EXPECT_EQ(p, (std::vector<double>{0.5, 0, 0.5}));
}

// Training set on a line: the 10 nearest neighbours of x = 0 are at 1..10 with labels 0,0,0,0,0,0,1,1,1,2
// (6/3/1), the rest far away, so that F = (50, 30, 20) as in the hand-computed case.
KnnClassifier LineClassifier(double floor) {
  std::vector<float> x;
  std::vector<int> labels;
  const int near_labels[10] = {0, 0, 0, 0, 0, 0, 1, 1, 1, 2};
  for (int i = 0; i < 10; ++i) {
    x.push_back(float(i + 1));
    labels.push_back(near_labels[i]);
  }
  const int remaining[3] = {50 - 6, 30 - 3, 20 - 1};
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < remaining[c]; ++i) {
      x.push_back(float(1000 + 10 * c + 0.01 * i));
      labels.push_back(c);
    }
  KnnOptions options;
  options.probability_floor = floor;
  return KnnClassifier::Train(x, 1, labels, 3, options).value();
}

TEST(KnnClassifier, CountsTheTenNearestAndAppliesEq4) {
  const KnnClassifier knn = LineClassifier(0.0);
  EXPECT_EQ(knn.class_counts(), (std::vector<int64_t>{50, 30, 20}));
  const float z = -0.5f;
  EXPECT_EQ(knn.NeighbourCounts({&z, 1}), (std::vector<int>{6, 3, 1}));
  const std::vector<double> p = knn.Probabilities({&z, 1});
  EXPECT_NEAR(p[0], 27.0 / 53.0, 1e-12);
  EXPECT_NEAR(p[1], 18.0 / 53.0, 1e-12);
  EXPECT_NEAR(p[2], 8.0 / 53.0, 1e-12);
}

TEST(KnnClassifier, FloorKeepsEveryProbabilityPositiveAndSummingToOne) {
  const KnnClassifier knn = LineClassifier(1e-3);
  const float z = 1000.0f;  // All ten neighbours are class 0.
  const std::vector<double> p = knn.Probabilities({&z, 1});
  EXPECT_NEAR(std::accumulate(p.begin(), p.end(), 0.0), 1.0, 1e-12);
  EXPECT_GT(p[0], 0.99);
  EXPECT_GE(p[1], 1e-3 / (1 + 2e-3));
}

TEST(KnnClassifier, SaveLoadRoundTripGivesTheSameProbabilities) {
  const KnnClassifier knn = LineClassifier(1e-3);
  const std::string path = ::testing::TempDir() + "/knn_roundtrip.bin";
  ASSERT_TRUE(knn.Save(path).ok());
  Result<KnnClassifier> loaded = KnnClassifier::Load(path);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  for (float z : {-3.0f, 0.0f, 4.5f, 1000.0f, 1015.0f, 2000.0f})
    EXPECT_EQ(knn.Probabilities({&z, 1}), loaded->Probabilities({&z, 1})) << z;
  std::remove(path.c_str());
}

// Ten points 0..9 on a line, raw coordinates, k = 2: a point's two nearest others are 1 and 1 away (1 and 2 at
// the ends: 1.5). The leave-one-out distances are eight 1s and two 1.5s.
TEST(KnnClassifier, NeighbourDistanceAndTheTrainingQuantileLeaveEachObservationOut) {
  std::vector<float> x;
  std::vector<int> labels;
  for (int i = 0; i < 10; ++i) x.push_back(float(i)), labels.push_back(i % 2);
  KnnOptions options;
  options.k = 2;
  options.standardise = false;
  const KnnClassifier knn = KnnClassifier::Train(x, 1, labels, 2, options).value();
  const float far = 20.0f, mid = 4.5f, on = 3.0f;
  EXPECT_NEAR(knn.NeighbourDistance({&far, 1}), (11.0 + 12.0) / 2, 1e-6);
  EXPECT_NEAR(knn.NeighbourDistance({&mid, 1}), 0.5, 1e-6);
  EXPECT_NEAR(knn.NeighbourDistance({&on, 1}), 0.5, 1e-6);  // A training point counts itself: 0 and 1.
  EXPECT_NEAR(knn.TrainingNeighbourDistanceQuantile(0.5), 1.0, 1e-9);
  EXPECT_NEAR(knn.TrainingNeighbourDistanceQuantile(1.0), 1.5, 1e-9);
  EXPECT_NEAR(knn.TrainingNeighbourDistanceQuantile(7.65 / 9), 1.0 + 0.65 * 0.5, 1e-9);  // Between the 8th and 9th.
  EXPECT_NEAR(knn.TrainingNeighbourDistanceQuantile(0.0), 1.0, 1e-9);
  // Over 5 of the 10 observations at an even stride (0, 2, 4, 6, 8), each still against all the others.
  EXPECT_NEAR(knn.TrainingNeighbourDistanceQuantile(1.0, 5), 1.5, 1e-9);
  EXPECT_NEAR(knn.TrainingNeighbourDistanceQuantile(0.5, 5), 1.0, 1e-9);
  // Probabilities and the distance from one search.
  double d = 0;
  EXPECT_EQ(knn.Probabilities({&far, 1}, &d), knn.Probabilities({&far, 1}));
  EXPECT_DOUBLE_EQ(d, knn.NeighbourDistance({&far, 1}));
  // Exact duplicates: only the observation itself is left out, its twin is a neighbour at 0.
  const KnnClassifier twins = KnnClassifier::Train({0.f, 0.f, 5.f}, 1, {0, 0, 1}, 2, [] {
    KnnOptions o;
    o.k = 1;
    o.standardise = false;
    return o;
  }()).value();
  EXPECT_NEAR(twins.TrainingNeighbourDistanceQuantile(0.0), 0.0, 1e-9);
  EXPECT_NEAR(twins.TrainingNeighbourDistanceQuantile(1.0), 5.0, 1e-9);
  // Standardised: distances are in standard deviations of the training set (of 0..9: sqrt(8.25)), so a query 11
  // and 12 units from its two neighbours lies 11.5 / sqrt(8.25) from them on average.
  options.standardise = true;
  const KnnClassifier standardised = KnnClassifier::Train(x, 1, labels, 2, options).value();
  EXPECT_NEAR(standardised.NeighbourDistance({&far, 1}), 11.5 / std::sqrt(8.25), 1e-5);
}

TEST(KnnClassifier, RejectsBadInputWithFieldNames) {
  Result<KnnClassifier> r = KnnClassifier::Train({1, 2}, 1, {0, 5}, 3, {});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("label 5"), std::string::npos);
  KnnOptions bad;
  bad.k = 0;
  r = KnnClassifier::Train({1}, 1, {0}, 1, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("k = 0"), std::string::npos);
  EXPECT_FALSE(KnnClassifier::Load("/nonexistent/model.bin").ok());
}

}  // namespace
}  // namespace semvox
