#include "perception/spanning_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace semvox {
namespace {

double TotalWeight(const std::vector<WeightedEdge>& edges) {
  double s = 0;
  for (const auto& e : edges) s += e.weight;
  return s;
}

TEST(EuclideanMinimumSpanningTree, PointsOnALineChainInOrder) {
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {6, 0, 0}, {1, 0, 0}, {3, 0, 0}};
  const std::vector<WeightedEdge> mst = EuclideanMinimumSpanningTree(p);
  const std::vector<WeightedEdge> expected = {{0, 2, 1.0}, {2, 3, 2.0}, {1, 3, 3.0}};
  EXPECT_EQ(mst, expected);
}

TEST(EuclideanMinimumSpanningTree, SquareWithCentreIsAStar) {
  // Corners of a 2 m square and its centre: every corner is sqrt(2) from the centre and 2 from its
  // neighbours, so the tree is the star through the centre (total 4 sqrt 2).
  const std::vector<Eigen::Vector3d> p = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}, {1, 1, 0}};
  const std::vector<WeightedEdge> mst = EuclideanMinimumSpanningTree(p);
  ASSERT_EQ(mst.size(), 4u);
  for (const auto& e : mst) {
    EXPECT_EQ(e.j, 4);
    EXPECT_NEAR(e.weight, std::sqrt(2.0), 1e-12);
  }
  EXPECT_NEAR(TotalWeight(mst), 4 * std::sqrt(2.0), 1e-12);
}

TEST(EuclideanMinimumSpanningTree, SameWeightAsKruskalOnTheCompleteGraph) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Eigen::Vector3d> p(size_t(5 + trial * 7));
    for (auto& q : p) q = {u(rng), u(rng), u(rng)};
    std::vector<WeightedEdge> all;
    for (int i = 0; i < int(p.size()); ++i)
      for (int j = i + 1; j < int(p.size()); ++j) all.push_back({i, j, (p[size_t(i)] - p[size_t(j)]).norm()});
    const auto prim = EuclideanMinimumSpanningTree(p);
    const auto kruskal = MinimumSpanningForest(int(p.size()), all);
    ASSERT_EQ(prim.size(), p.size() - 1);
    ASSERT_EQ(kruskal.size(), p.size() - 1);
    EXPECT_NEAR(TotalWeight(prim), TotalWeight(kruskal), 1e-9);
  }
}

TEST(EuclideanMinimumSpanningTree, EmptyAndSinglePoint) {
  EXPECT_TRUE(EuclideanMinimumSpanningTree(std::vector<Eigen::Vector3d>{}).empty());
  EXPECT_TRUE(EuclideanMinimumSpanningTree(std::vector<Eigen::Vector3d>{{1, 2, 3}}).empty());
}

TEST(MinimumSpanningForest, KeepsComponentsApartAndSkipsBadEdges) {
  // Two components {0,1,2} and {3,4}; a heavier edge closing the triangle is dropped.
  const std::vector<WeightedEdge> candidates = {{0, 1, 1}, {1, 2, 2}, {0, 2, 5}, {4, 3, 1}, {2, 2, 0}, {0, 9, 0}};
  const std::vector<WeightedEdge> forest = MinimumSpanningForest(5, candidates);
  const std::vector<WeightedEdge> expected = {{0, 1, 1}, {3, 4, 1}, {1, 2, 2}};
  EXPECT_EQ(forest, expected);
}

}  // namespace
}  // namespace semvox
