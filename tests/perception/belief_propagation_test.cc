// Exact tree BP against brute-force enumeration, and loopy BP against exact BP on trees.
#include "perception/belief_propagation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace semvox {
namespace {

// A random tree on n nodes (each node i > 0 joins a random earlier node), with `drop` of its edges
// removed to make a forest, random log potentials in [-2, 2].
PairwiseModel RandomForest(int n, int m, int drop, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-2, 2);
  PairwiseModel model;
  model.num_labels = m;
  model.log_unary.resize(size_t(n) * size_t(m));
  for (double& v : model.log_unary) v = u(*rng);
  for (int i = 1; i < n; ++i) {
    std::uniform_int_distribution<int> parent(0, i - 1);
    PairwiseModel::Edge e;
    // Random orientation, so both (i, j) conventions are exercised.
    const int p = parent(*rng);
    if ((*rng)() % 2) e = {p, i, {}}; else e = {i, p, {}};
    e.log_pairwise.resize(size_t(m) * size_t(m));
    for (double& v : e.log_pairwise) v = u(*rng);
    model.edges.push_back(e);
  }
  for (int d = 0; d < drop && !model.edges.empty(); ++d) model.edges.erase(model.edges.begin() + long((*rng)() % model.edges.size()));
  return model;
}

struct BruteForce {
  std::vector<double> marginals;
  double log_z = 0;
  std::vector<int> map;
  double map_score = -1e300;
};

BruteForce Enumerate(const PairwiseModel& model) {
  const int n = model.num_nodes(), m = model.num_labels;
  BruteForce out;
  out.marginals.assign(size_t(n) * size_t(m), 0.0);
  std::vector<int> x(size_t(n), 0);
  std::vector<double> scores;
  std::vector<std::vector<int>> assignments;
  while (true) {
    const double s = model.LogScore(x);
    scores.push_back(s);
    assignments.push_back(x);
    if (s > out.map_score) {
      out.map_score = s;
      out.map = x;
    }
    int k = 0;
    while (k < n && ++x[size_t(k)] == m) x[size_t(k++)] = 0;
    if (k == n) break;
  }
  double mx = -1e300;
  for (double s : scores) mx = std::max(mx, s);
  double z = 0;
  for (double s : scores) z += std::exp(s - mx);
  out.log_z = mx + std::log(z);
  for (size_t a = 0; a < scores.size(); ++a) {
    const double p = std::exp(scores[a] - out.log_z);
    for (int i = 0; i < n; ++i) out.marginals[size_t(i) * m + size_t(assignments[a][size_t(i)])] += p;
  }
  return out;
}

TEST(TreeSumProduct, EqualsBruteForceOnSmallRandomTreesAndForests) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 1 + trial % 7, m = 2 + trial % 3, drop = trial % 4 == 3 ? 2 : 0;
    const PairwiseModel model = RandomForest(n, m, drop, &rng);
    const BruteForce bf = Enumerate(model);
    Marginals marg;
    ASSERT_TRUE(TreeSumProduct(model, &marg).ok());
    ASSERT_EQ(marg.p.size(), bf.marginals.size());
    for (size_t k = 0; k < marg.p.size(); ++k) EXPECT_NEAR(marg.p[k], bf.marginals[k], 1e-10) << "trial " << trial;
    EXPECT_NEAR(marg.log_partition, bf.log_z, 1e-9) << "trial " << trial;
  }
}

TEST(TreeMaxProduct, EqualsBruteForceOnSmallRandomTreesAndForests) {
  std::mt19937 rng(43);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 1 + trial % 7, m = 2 + trial % 3, drop = trial % 4 == 3 ? 2 : 0;
    const PairwiseModel model = RandomForest(n, m, drop, &rng);
    const BruteForce bf = Enumerate(model);
    std::vector<int> map;
    ASSERT_TRUE(TreeMaxProduct(model, &map).ok());
    EXPECT_EQ(map, bf.map) << "trial " << trial;  // Continuous random potentials: the maximiser is unique.
    EXPECT_NEAR(model.LogScore(map), bf.map_score, 1e-12);
  }
}

TEST(TreeSumProduct, MarginalsSumToOneOnALargeTree) {
  std::mt19937 rng(5);
  const PairwiseModel model = RandomForest(2000, 6, 0, &rng);
  Marginals marg;
  ASSERT_TRUE(TreeSumProduct(model, &marg).ok());
  for (int v = 0; v < model.num_nodes(); ++v) {
    double s = 0;
    for (int a = 0; a < 6; ++a) s += marg.at(v, a);
    EXPECT_NEAR(s, 1.0, 1e-12);
  }
}

TEST(TreeInference, RejectsCyclesAndDuplicateEdges) {
  PairwiseModel model;
  model.num_labels = 2;
  model.log_unary.assign(6, 0.0);
  const std::vector<double> psi(4, 0.0);
  model.edges = {{0, 1, psi}, {1, 2, psi}, {2, 0, psi}};
  Marginals marg;
  std::vector<int> map;
  Status st = TreeSumProduct(model, &marg);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("cycle"), std::string::npos) << st.message();
  EXPECT_FALSE(TreeMaxProduct(model, &map).ok());
  model.edges = {{0, 1, psi}, {1, 0, psi}};
  EXPECT_FALSE(TreeSumProduct(model, &marg).ok());
  model.edges = {{0, 3, psi}};
  EXPECT_NE(TreeSumProduct(model, &marg).message().find("edge 0 = (0, 3)"), std::string::npos);
}

TEST(LoopyBeliefPropagation, EqualsExactBpOnATree) {
  std::mt19937 rng(44);
  for (int trial = 0; trial < 30; ++trial) {
    const int n = 2 + trial * 5, m = 2 + trial % 4;
    const PairwiseModel model = RandomForest(n, m, trial % 3, &rng);
    Marginals exact, loopy;
    ASSERT_TRUE(TreeSumProduct(model, &exact).ok());
    LoopyBpSummary summary;
    ASSERT_TRUE(LoopyBeliefPropagation(model, LoopyBpOptions{}, &loopy, &summary).ok());
    EXPECT_TRUE(summary.converged) << "trial " << trial;
    EXPECT_LE(summary.iterations, n + 1);  // Flooding needs at most diameter + 1 sweeps on a tree.
    for (size_t k = 0; k < exact.p.size(); ++k) EXPECT_NEAR(loopy.p[k], exact.p[k], 1e-8) << "trial " << trial;
    std::vector<int> map;
    ASSERT_TRUE(TreeMaxProduct(model, &map).ok());
    (void)map;  // Max-marginal decoding need not equal the joint MAP; only the marginals are compared.
  }
}

TEST(LoopyBeliefPropagation, ConvergesToNormalisedBeliefsOnAGridWithLoops) {
  std::mt19937 rng(45);
  std::uniform_real_distribution<double> u(-1, 1);
  const int side = 8, m = 3;
  PairwiseModel model;
  model.num_labels = m;
  model.log_unary.resize(size_t(side * side * m));
  for (double& v : model.log_unary) v = u(rng);
  // Attractive Potts edges, weak enough for BP to converge.
  std::vector<double> potts(size_t(m * m), 0.0);
  for (int a = 0; a < m; ++a) potts[size_t(a * m + a)] = 0.3;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      if (x + 1 < side) model.edges.push_back({y * side + x, y * side + x + 1, potts});
      if (y + 1 < side) model.edges.push_back({y * side + x, (y + 1) * side + x, potts});
    }
  Marginals marg;
  LoopyBpOptions options;
  options.damping = 0.3;
  LoopyBpSummary summary;
  ASSERT_TRUE(LoopyBeliefPropagation(model, options, &marg, &summary).ok());
  EXPECT_TRUE(summary.converged);
  for (int v = 0; v < side * side; ++v) {
    double s = 0;
    for (int a = 0; a < m; ++a) s += marg.at(v, a);
    EXPECT_NEAR(s, 1.0, 1e-12);
  }
  Marginals tree;
  EXPECT_FALSE(TreeSumProduct(model, &tree).ok());  // The grid has loops.
}

TEST(LoopyBeliefPropagation, PottsEdgesAgreeWithTheGeneralMessage) {
  // Potts edges (as the view CRFs build them) take an O(m) message; the same model with one entry of every
  // edge moved by 1e-13 is not Potts and takes the general O(m^2) sum. Attractive and repulsive edges,
  // a loopy grid of 22 labels (the second level's count).
  std::mt19937 rng(46);
  std::uniform_real_distribution<double> u(-2, 2), w(-1.5, 1.0);
  const int side = 7, m = 22;
  PairwiseModel potts;
  potts.num_labels = m;
  potts.log_unary.resize(size_t(side * side * m));
  for (double& v : potts.log_unary) v = u(rng);
  auto edge = [&](int i, int j) {
    const double diag = w(rng), off = w(rng) * 0.3;
    PairwiseModel::Edge e{i, j, std::vector<double>(size_t(m * m), off)};
    for (int a = 0; a < m; ++a) e.log_pairwise[size_t(a * m + a)] = diag;
    return e;
  };
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      if (x + 1 < side) potts.edges.push_back(edge(y * side + x, y * side + x + 1));
      if (y + 1 < side) potts.edges.push_back(edge(y * side + x, (y + 1) * side + x));
    }
  PairwiseModel general = potts;
  for (auto& e : general.edges) e.log_pairwise[1] += 1e-13;
  LoopyBpOptions options;
  options.damping = 0.5;
  options.max_iterations = 60;
  Marginals a, b;
  LoopyBpSummary sa, sb;
  ASSERT_TRUE(LoopyBeliefPropagation(potts, options, &a, &sa).ok());
  ASSERT_TRUE(LoopyBeliefPropagation(general, options, &b, &sb).ok());
  EXPECT_EQ(sa.iterations, sb.iterations);
  ASSERT_EQ(a.p.size(), b.p.size());
  for (size_t k = 0; k < a.p.size(); ++k) EXPECT_NEAR(a.p[k], b.p[k], 1e-9) << k;
  // On a tree (a path through the grid) the Potts messages give the exact marginals.
  PairwiseModel path = potts;
  path.edges.clear();
  for (int v = 0; v + 1 < side * side; ++v) path.edges.push_back(edge(v, v + 1));
  Marginals exact, loopy;
  ASSERT_TRUE(TreeSumProduct(path, &exact).ok());
  ASSERT_TRUE(LoopyBeliefPropagation(path, LoopyBpOptions{}, &loopy).ok());
  for (size_t k = 0; k < exact.p.size(); ++k) EXPECT_NEAR(loopy.p[k], exact.p[k], 1e-9) << k;
}

TEST(LoopyBeliefPropagation, RejectsBadOptions) {
  PairwiseModel model;
  model.num_labels = 2;
  model.log_unary.assign(2, 0.0);
  LoopyBpOptions options;
  options.damping = 1.0;
  Marginals marg;
  const Status st = LoopyBeliefPropagation(model, options, &marg);
  EXPECT_NE(st.message().find("damping = 1"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace semvox
