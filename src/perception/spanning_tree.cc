#include "perception/spanning_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace semvox {

UnionFind::UnionFind(int n) : parent_(static_cast<size_t>(std::max(n, 0))), size_(parent_.size(), 1) {
  std::iota(parent_.begin(), parent_.end(), 0);
}

int UnionFind::Find(int x) {
  while (parent_[size_t(x)] != x) {
    parent_[size_t(x)] = parent_[size_t(parent_[size_t(x)])];
    x = parent_[size_t(x)];
  }
  return x;
}

bool UnionFind::Union(int a, int b) {
  a = Find(a);
  b = Find(b);
  if (a == b) return false;
  if (size_[size_t(a)] < size_[size_t(b)]) std::swap(a, b);
  parent_[size_t(b)] = a;
  size_[size_t(a)] += size_[size_t(b)];
  return true;
}

std::vector<WeightedEdge> EuclideanMinimumSpanningTree(std::span<const Eigen::Vector3d> points) {
  const int n = int(points.size());
  std::vector<WeightedEdge> edges;
  if (n < 2) return edges;
  edges.reserve(size_t(n - 1));
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> best(size_t(n), kInf);  // Squared distance to the tree.
  std::vector<int> from(size_t(n), -1);
  std::vector<char> in_tree(size_t(n), 0);
  int current = 0;
  in_tree[0] = 1;
  for (int added = 1; added < n; ++added) {
    int next = -1;
    double next_d = kInf;
    for (int v = 0; v < n; ++v) {
      if (in_tree[size_t(v)]) continue;
      const double d = (points[size_t(v)] - points[size_t(current)]).squaredNorm();
      if (d < best[size_t(v)]) {
        best[size_t(v)] = d;
        from[size_t(v)] = current;
      }
      if (best[size_t(v)] < next_d) {
        next_d = best[size_t(v)];
        next = v;
      }
    }
    in_tree[size_t(next)] = 1;
    const int a = std::min(next, from[size_t(next)]), b = std::max(next, from[size_t(next)]);
    edges.push_back({a, b, std::sqrt(next_d)});
    current = next;
  }
  return edges;
}

std::vector<WeightedEdge> MinimumSpanningForest(int num_nodes, std::vector<WeightedEdge> candidates) {
  for (WeightedEdge& e : candidates)
    if (e.i > e.j) std::swap(e.i, e.j);
  std::sort(candidates.begin(), candidates.end(), [](const WeightedEdge& a, const WeightedEdge& b) {
    if (a.weight != b.weight) return a.weight < b.weight;
    return a.i != b.i ? a.i < b.i : a.j < b.j;
  });
  UnionFind sets(num_nodes);
  std::vector<WeightedEdge> forest;
  for (const WeightedEdge& e : candidates) {
    if (e.i == e.j || e.i < 0 || e.j >= num_nodes) continue;
    if (sets.Union(e.i, e.j)) forest.push_back(e);
  }
  return forest;
}

}  // namespace semvox
