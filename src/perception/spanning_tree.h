// Minimum spanning trees for the view CRFs' graphs (MST-CRF paper Sec. 3.2; heterogeneous-coverage paper
// Sec. III-B/C): the tree over the Euclidean distances between 3D superpixel centroids, and the minimum
// spanning forest of a candidate edge set (superpixels without depth joined over LAB colour distance).
#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

namespace semvox {

struct WeightedEdge {
  int i = 0, j = 0;  // Node indices, i < j.
  double weight = 0;
  bool operator==(const WeightedEdge&) const = default;
};

// Minimum spanning tree of the complete graph over `points` with Euclidean edge weights (Prim, O(n^2)
// time, O(n) memory: fine for the ~1000 superpixels of a view). n - 1 edges for n >= 1 points; ties go to
// the lower index, so the result is deterministic.
std::vector<WeightedEdge> EuclideanMinimumSpanningTree(std::span<const Eigen::Vector3d> points);

// Minimum spanning forest (Kruskal) of `num_nodes` nodes over `candidates` (any order, i != j, both in
// range; others are skipped). Equal weights are taken in (i, j) order.
std::vector<WeightedEdge> MinimumSpanningForest(int num_nodes, std::vector<WeightedEdge> candidates);

// Disjoint sets with path halving and union by size.
class UnionFind {
 public:
  explicit UnionFind(int n);
  int Find(int x);
  bool Union(int a, int b);  // False when already joined.

 private:
  std::vector<int> parent_, size_;
};

}  // namespace semvox
