#include "objects/random_forest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include "core/file_util.h"
#include "tests/test_util.h"

namespace semvox {
namespace {

// Class c (0, 1, 2) is decided by feature 0 alone (c = floor of x0, x0 in [0, 3)); features 1-5 are noise
// on a scale 100 times larger. A classifier that weighs every standardised dimension alike is confused by
// the noise; a tree finds the one dimension that matters.
void Rows(int n, uint64_t seed, std::vector<float>* x, std::vector<int>* y) {
  std::mt19937 rng(static_cast<uint32_t>(seed));
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int i = 0; i < n; ++i) {
    const float x0 = 3.f * u(rng);
    x->push_back(x0);
    for (int k = 1; k < 6; ++k) x->push_back(300.f * u(rng));
    y->push_back(std::min(2, int(x0)));
  }
}

RandomForestOptions Small() {
  RandomForestOptions o;
  o.trees = 30;
  o.features_per_split = 3;
  return o;
}

TEST(RandomForest, FindsTheOneInformativeFeatureAmongNoise) {
  std::vector<float> x, tx;
  std::vector<int> y, ty;
  Rows(600, 1, &x, &y);
  Rows(300, 2, &tx, &ty);
  Result<RandomForest> rf = RandomForest::Train(x, 6, y, 3, Small());
  ASSERT_TRUE(rf.ok()) << rf.status().message();
  EXPECT_EQ(rf->dims(), 6);
  EXPECT_EQ(rf->num_classes(), 3);
  EXPECT_EQ(rf->num_trees(), 30);
  int correct = 0;
  for (size_t i = 0; i < ty.size(); ++i) {
    const std::vector<double> p = rf->Probabilities({&tx[i * 6], 6});
    ASSERT_EQ(p.size(), 3u);
    double sum = 0;
    for (double v : p) {
      EXPECT_GE(v, 1e-3 / 1.003 - 1e-12);  // The probability floor, after renormalising.
      sum += v;
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
    correct += int(std::max_element(p.begin(), p.end()) - p.begin()) == ty[i];
  }
  // Only rows within a few hundredths of a class boundary can be wrong.
  EXPECT_GE(correct, int(0.95 * ty.size()));
}

TEST(RandomForest, SameRowsAndSeedGiveTheSameModelOtherSeedsAnother) {
  std::vector<float> x;
  std::vector<int> y;
  Rows(300, 3, &x, &y);
  Result<RandomForest> a = RandomForest::Train(x, 6, y, 3, Small());
  Result<RandomForest> b = RandomForest::Train(x, 6, y, 3, Small());
  RandomForestOptions other = Small();
  other.seed = 2;
  Result<RandomForest> c = RandomForest::Train(x, 6, y, 3, other);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  testing::ScratchDir dir("forest_determinism");
  ASSERT_TRUE(a->Save(dir.File("a")).ok());
  ASSERT_TRUE(b->Save(dir.File("b")).ok());
  ASSERT_TRUE(c->Save(dir.File("c")).ok());
  std::string sa, sb, sc;
  ASSERT_TRUE(ReadFileBytes(dir.File("a"), &sa).ok());
  ASSERT_TRUE(ReadFileBytes(dir.File("b"), &sb).ok());
  ASSERT_TRUE(ReadFileBytes(dir.File("c"), &sc).ok());
  EXPECT_EQ(sa, sb);
  EXPECT_NE(sa, sc);
}

TEST(RandomForest, SaveLoadRoundTripGivesTheSameProbabilities) {
  std::vector<float> x;
  std::vector<int> y;
  Rows(300, 4, &x, &y);
  Result<RandomForest> rf = RandomForest::Train(x, 6, y, 3, Small());
  ASSERT_TRUE(rf.ok());
  testing::ScratchDir dir("forest_roundtrip");
  ASSERT_TRUE(rf->Save(dir.File("m.forest")).ok());
  Result<RandomForest> back = RandomForest::Load(dir.File("m.forest"));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_EQ(back->num_nodes(), rf->num_nodes());
  for (size_t i = 0; i < 50; ++i) {
    const std::vector<double> p = rf->Probabilities({&x[i * 6], 6}), q = back->Probabilities({&x[i * 6], 6});
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[size_t(k)], q[size_t(k)], 1e-6);
  }
}

TEST(RandomForest, BalancedClassesLetARareClassWin) {
  // Class 1 is every fifth row with x0 in [2.5, 3) (about 3 % of all rows), mixed with four times as many
  // class-0 rows there. Unbalanced, the region's majority is class 0; balanced, class 1.
  std::vector<float> x;
  std::vector<int> y;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int i = 0; i < 2000; ++i) {
    const float x0 = 3.f * u(rng);
    x.push_back(x0);
    y.push_back(x0 >= 2.5f && i % 5 == 0 ? 1 : 0);
  }
  RandomForestOptions o;
  o.trees = 20;
  o.features_per_split = 1;
  o.min_leaf = 60;  // Leaves too large to isolate single rows.
  Result<RandomForest> plain = RandomForest::Train(x, 1, y, 2, o);
  o.balance_classes = true;
  Result<RandomForest> balanced = RandomForest::Train(x, 1, y, 2, o);
  ASSERT_TRUE(plain.ok() && balanced.ok());
  const float q = 2.75f;
  EXPECT_LT(plain->Probabilities({&q, 1})[1], 0.5);
  EXPECT_GT(balanced->Probabilities({&q, 1})[1], 0.5);
  const float low = 1.0f;
  EXPECT_LT(balanced->Probabilities({&low, 1})[1], 0.1);
}

TEST(RandomForest, RejectsBadInputAndBadFiles) {
  EXPECT_FALSE(RandomForest::Train(std::vector<float>{1, 2}, 1, std::vector<int>{0, 5}, 3, {}).ok());  // Label out of range.
  EXPECT_FALSE(RandomForest::Train(std::vector<float>{1, 2, 3}, 2, std::vector<int>{0, 1}, 3, {}).ok());  // Ragged rows.
  EXPECT_FALSE(RandomForest::Train(std::vector<float>{}, 2, std::vector<int>{}, 3, {}).ok());
  EXPECT_FALSE(RandomForest::Train(std::vector<float>{NAN}, 1, std::vector<int>{0}, 3, {}).ok());
  RandomForestOptions bad;
  bad.trees = 0;
  EXPECT_FALSE(RandomForest::Train(std::vector<float>{1}, 1, std::vector<int>{0}, 3, bad).ok());

  testing::ScratchDir dir("forest_bad");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.File(name)) << text;
    return dir.File(name);
  };
  const std::string header = "semvox_random_forest 1\n1 2 1 0.001\n";
  Result<RandomForest> ok = RandomForest::Load(write("ok", header + "tree 3\nS 0 0.5 1 2\nL 1 0 1\nL 1 1 1\n"));
  ASSERT_TRUE(ok.ok()) << ok.status().message();
  const float lo = 0.2f, hi = 0.9f;
  EXPECT_GT(ok->Probabilities({&lo, 1})[0], 0.99);
  EXPECT_GT(ok->Probabilities({&hi, 1})[1], 0.99);
  for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
           {"magic", "semvox_knn 1\n"},
           {"cycle", header + "tree 3\nS 0 0.5 0 2\nL 1 0 1\nL 1 1 1\n"},         // A child pointing back.
           {"feature", header + "tree 3\nS 4 0.5 1 2\nL 1 0 1\nL 1 1 1\n"},       // Feature 4 of 1.
           {"class", header + "tree 3\nS 0 0.5 1 2\nL 1 7 1\nL 1 1 1\n"},         // Class 7 of 2.
           {"truncated", header + "tree 3\nS 0 0.5 1 2\nL 1 0 1\n"}}) {
    const std::string path = write(name, text);
    Result<RandomForest> r = RandomForest::Load(path);
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_NE(r.status().message().find(path), std::string::npos) << r.status().message();
  }
  EXPECT_FALSE(RandomForest::Load(dir.File("absent")).ok());
}

}  // namespace
}  // namespace semvox
