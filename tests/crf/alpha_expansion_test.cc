#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "crf/alpha_expansion_impl.h"
#include "crf/energy.h"
#include "crf/max_flow.h"
#include "crf/solvers.h"
#include "tests/crf/crf_test_util.h"

namespace semvox {
namespace {

using testing::BruteForceMinimum;
using testing::MakeRandomEnergy;
using testing::RandomEnergySpec;

std::vector<CrfLabel> RandomLabels(int n, int L, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<CrfLabel> x(n);
  for (CrfLabel& l : x) l = static_cast<CrfLabel>(rng() % L);
  return x;
}

// A w x h 4-connected Potts grid whose truth is diagonal bands of block_x x block_y cells: unary 0 for the
// band's label and off_cost for the others, plus unit(rng) noise; every edge weight `potts`.
CrfEnergy NoisyBandGrid(int w, int h, int L, int block_x, int block_y, float off_cost, float potts, std::mt19937_64* rng) {
  CrfEnergy energy(w * h, L);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int truth = (x / block_x + y / block_y) % L;
      for (int l = 0; l < L; ++l) energy.SetUnary(y * w + x, l, (l == truth ? 0.0f : off_cost) + unit(*rng));
      if (x + 1 < w) energy.AddEdge(y * w + x, y * w + x + 1, potts);
      if (y + 1 < h) energy.AddEdge(y * w + x, (y + 1) * w + x, potts);
    }
  return energy;
}

void ExpectMonotone(const CrfSolverSummary& s, const std::string& what) {
  double previous = s.initial_energy;
  for (size_t k = 0; k < s.energy_per_expansion.size(); ++k) {
    ASSERT_LE(s.energy_per_expansion[k], previous + 1e-9 * (1 + std::abs(previous))) << what << " expansion " << k;
    previous = s.energy_per_expansion[k];
  }
  previous = s.initial_energy;
  for (size_t k = 0; k < s.energy_per_sweep.size(); ++k) {
    ASSERT_LE(s.energy_per_sweep[k], previous + 1e-9 * (1 + std::abs(previous))) << what << " sweep " << k;
    previous = s.energy_per_sweep[k];
  }
  ASSERT_LE(s.final_energy, s.initial_energy + 1e-9 * (1 + std::abs(s.initial_energy))) << what;
}

TEST(AlphaExpansion, NeverIncreasesEnergy) {
  int problems = 0;
  for (uint64_t seed = 0; seed < 400; ++seed) {
   for (bool prune : {true, false}) {
    RandomEnergySpec spec;
    spec.num_nodes = 5 + static_cast<int>(seed % 40);
    spec.num_labels = 2 + static_cast<int>(seed % 5);
    spec.edge_probability = 0.05 + 0.05 * static_cast<double>(seed % 6);
    spec.num_cliques = static_cast<int>(seed % 4);
    spec.metric_model = seed % 3 == 1;
    spec.nonmetric_model = seed % 5 == 2;  // Truncated moves, rejected when they would raise E.
    spec.weighted_cliques = seed % 2 == 1;
    spec.negative_unaries = seed % 7 == 3;
    const CrfEnergy energy = MakeRandomEnergy(spec, seed);
    ASSERT_TRUE(energy.Check(nullptr));
    AlphaExpansionOptions options;
    options.initial_labelling = InitialLabelling::kGiven;
    options.randomize_label_order = seed % 2 == 0;
    options.seed = seed;
    options.prune_decided_nodes = prune;
    std::vector<CrfLabel> labels = RandomLabels(spec.num_nodes, spec.num_labels, seed + 99);
    CrfSolverSummary summary;
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &labels, &summary).ok());
    ExpectMonotone(summary, "seed " + std::to_string(seed));
    EXPECT_NEAR(summary.final_energy, energy.Evaluate(labels), 1e-9 * (1 + std::abs(summary.final_energy)));
    EXPECT_TRUE(summary.converged);
    ++problems;
   }
  }
  EXPECT_EQ(problems, 800);
}

// Two labels, submodular pairwise terms (Potts, metric) and Robust P^n cliques (concave in the count,
// hence submodular): a labelling that no expansion improves is a global minimum.
TEST(AlphaExpansion, EqualsBruteForceMinimumForTwoLabelsSubmodular) {
  for (uint64_t seed = 0; seed < 150; ++seed) {
    RandomEnergySpec spec;
    spec.num_nodes = 3 + static_cast<int>(seed % 11);  // Up to 13 nodes: 8192 labellings.
    spec.num_labels = 2;
    spec.edge_probability = 0.2 + 0.1 * static_cast<double>(seed % 4);
    spec.num_cliques = static_cast<int>(seed % 3);
    spec.metric_model = seed % 2 == 0;
    spec.weighted_cliques = seed % 4 == 1;
    spec.negative_unaries = seed % 3 == 0;
    const CrfEnergy energy = MakeRandomEnergy(spec, 1000 + seed);
    for (InitialLabelling init : {InitialLabelling::kUnaryArgmin, InitialLabelling::kAllZero}) {
      AlphaExpansionOptions options;
      options.initial_labelling = init;
      std::vector<CrfLabel> labels;
      CrfSolverSummary summary;
      ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &labels, &summary).ok());
      const double optimum = BruteForceMinimum(energy);
      EXPECT_NEAR(summary.final_energy, optimum, 1e-6) << "seed " << seed;
      EXPECT_EQ(summary.num_truncated_terms, 0);
    }
  }
}

// Boykov, Veksler & Zabih 2001, Thm. 6.1: with a metric V and non-negative unaries, the expansion local
// minimum is within 2 c of the optimum, c = max_{a != b} V(a, b) / min_{a != b} V(a, b) (1 for Potts).
TEST(AlphaExpansion, WithinTheKnownFactorOfTheOptimumForMetricPairwise) {
  int strictly_suboptimal = 0;
  for (uint64_t seed = 0; seed < 120; ++seed) {
    RandomEnergySpec spec;
    spec.num_nodes = 4 + static_cast<int>(seed % 5);  // Up to 8 nodes.
    spec.num_labels = 3 + static_cast<int>(seed % 2);  // 3^8 or 4^8 labellings at most.
    spec.edge_probability = 0.5;
    spec.metric_model = seed % 2 == 1;
    const CrfEnergy energy = MakeRandomEnergy(spec, 2000 + seed);
    double c = 1;
    for (int m = 1; m < energy.num_models(); ++m) {
      ASSERT_TRUE(energy.IsMetric(m));
      double lo = 1e30, hi = 0;
      for (int a = 0; a < spec.num_labels; ++a)
        for (int b = 0; b < spec.num_labels; ++b)
          if (a != b) {
            lo = std::min<double>(lo, energy.ModelCost(m, a, b));
            hi = std::max<double>(hi, energy.ModelCost(m, a, b));
          }
      c = std::max(c, hi / lo);
    }
    AlphaExpansionOptions options;
    std::vector<CrfLabel> labels;
    CrfSolverSummary summary;
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &labels, &summary).ok());
    const double optimum = BruteForceMinimum(energy);
    EXPECT_GE(summary.final_energy, optimum - 1e-9);
    EXPECT_LE(summary.final_energy, 2 * c * optimum + 1e-9) << "seed " << seed;
    if (summary.final_energy > optimum + 1e-9) ++strictly_suboptimal;
  }
  // Random small problems are mostly solved exactly; the factor is a bound, not the typical gap.
  EXPECT_LT(strictly_suboptimal, 60);
}

// Whatever the terms, the result admits no improving expansion move: checked by enumerating every move
// of every label. This verifies the graph construction (pairwise and Robust P^n) and the max-flow together.
TEST(AlphaExpansion, ResultIsOptimalForEveryExpansionMove) {
  for (uint64_t seed = 0; seed < 160; ++seed) {
    RandomEnergySpec spec;
    spec.num_nodes = 4 + static_cast<int>(seed % 8);
    spec.num_labels = 2 + static_cast<int>(seed % 4);
    spec.edge_probability = 0.35;
    spec.num_cliques = 1 + static_cast<int>(seed % 3);
    spec.metric_model = seed % 2 == 0;
    spec.weighted_cliques = seed % 3 == 0;
    const CrfEnergy energy = MakeRandomEnergy(spec, 3000 + seed);
    AlphaExpansionOptions options;
    options.initial_labelling = InitialLabelling::kGiven;
    options.prune_decided_nodes = seed % 2 == 0;
    std::vector<CrfLabel> labels = RandomLabels(spec.num_nodes, spec.num_labels, seed);
    CrfSolverSummary summary;
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &labels, &summary).ok());
    const double e = energy.Evaluate(labels);
    const int n = spec.num_nodes;
    for (CrfLabel alpha = 0; alpha < spec.num_labels; ++alpha) {
      for (uint32_t mask = 0; mask < (1u << n); ++mask) {
        std::vector<CrfLabel> moved = labels;
        for (int k = 0; k < n; ++k)
          if ((mask >> k) & 1) moved[k] = alpha;
        ASSERT_GE(energy.Evaluate(moved), e - 1e-9 * (1 + std::abs(e))) << "seed " << seed << " alpha " << alpha;
      }
    }
  }
}

// Fixing the nodes whose move is decided before the cut is an exact reduction: the same optimal move,
// hence the same energy after every expansion (continuous random costs: no ties).
TEST(AlphaExpansion, PruningDecidedNodesChangesNothingButTheWork) {
  int64_t pruned = 0;
  for (uint64_t seed = 0; seed < 100; ++seed) {
    RandomEnergySpec spec;
    spec.num_nodes = 10 + static_cast<int>(seed % 50);
    spec.num_labels = 2 + static_cast<int>(seed % 6);
    spec.edge_probability = 0.1;
    spec.num_cliques = static_cast<int>(seed % 3);
    spec.metric_model = seed % 2 == 0;
    spec.weighted_cliques = seed % 3 == 0;
    const CrfEnergy energy = MakeRandomEnergy(spec, 7000 + seed);
    AlphaExpansionOptions with, without;
    without.prune_decided_nodes = false;
    std::vector<CrfLabel> a, b;
    CrfSolverSummary sa, sb;
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, with, &a, &sa).ok());
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, without, &b, &sb).ok());
    ASSERT_EQ(sa.energy_per_expansion.size(), sb.energy_per_expansion.size()) << "seed " << seed;
    for (size_t k = 0; k < sa.energy_per_expansion.size(); ++k) {
      ASSERT_NEAR(sa.energy_per_expansion[k], sb.energy_per_expansion[k], 1e-9) << "seed " << seed << " move " << k;
    }
    EXPECT_EQ(a, b) << "seed " << seed;
    EXPECT_EQ(sb.num_pruned_nodes, 0);
    pruned += sa.num_pruned_nodes;
  }
  EXPECT_GT(pruned, 1000);  // The reduction does happen.
}

TEST(AlphaExpansion, RobustPnCliqueMakesAGroupAgree) {
  // Ten nodes on a chain, unaries weakly prefer label 1 on three of them, label 0 elsewhere; no pairwise
  // terms. A clique over all of them with a strong consistency reward relabels the minority.
  CrfEnergy energy(10, 2);
  for (int i = 0; i < 10; ++i) {
    const bool minority = i == 2 || i == 5 || i == 7;
    energy.SetUnary(i, 0, minority ? 0.3f : 0.0f);
    energy.SetUnary(i, 1, minority ? 0.0f : 0.3f);
  }
  std::vector<int> all(10);
  for (int i = 0; i < 10; ++i) all[i] = i;
  RobustPnParams p;
  p.gamma_max = 5;
  p.truncation_q = 5;
  energy.AddRobustPnClique(all, p);
  std::vector<CrfLabel> labels;
  CrfSolverSummary summary;
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, AlphaExpansionOptions(), &labels, &summary).ok());
  EXPECT_EQ(labels, std::vector<CrfLabel>(10, 0));
  EXPECT_NEAR(summary.final_energy, 0.9, 1e-6);
}

TEST(AlphaExpansion, DeterministicForAGivenSeed) {
  RandomEnergySpec spec;
  spec.num_nodes = 300;
  spec.num_labels = 6;
  spec.edge_probability = 0.02;
  spec.num_cliques = 3;
  const CrfEnergy energy = MakeRandomEnergy(spec, 77);
  AlphaExpansionOptions options;
  options.randomize_label_order = true;
  options.seed = 42;
  std::vector<CrfLabel> a, b;
  CrfSolverSummary sa, sb;
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &a, &sa).ok());
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &b, &sb).ok());
  EXPECT_EQ(a, b);
  EXPECT_EQ(sa.energy_per_expansion, sb.energy_per_expansion);
}

TEST(AlphaExpansion, BadOptionsNameTheField) {
  CrfEnergy energy(3, 2);
  AlphaExpansionOptions options;
  options.max_sweeps = 0;
  std::vector<CrfLabel> labels;
  CrfSolverSummary summary;
  const Status st = MinimizeWithAlphaExpansion(energy, options, &labels, &summary);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("max_sweeps = 0"), std::string::npos) << st.message();
}

TEST(AlphaExpansion, BadGivenLabelsAreRejected) {
  CrfEnergy energy(3, 2);
  AlphaExpansionOptions options;
  options.initial_labelling = InitialLabelling::kGiven;
  std::vector<CrfLabel> labels{0, 2, 1};
  CrfSolverSummary summary;
  const Status st = MinimizeWithAlphaExpansion(energy, options, &labels, &summary);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("node 1 has label 2"), std::string::npos) << st.message();
}

TEST(AlphaExpansion, PottsGridRecoversBlocksAndBeatsIcm) {
  // A 40 x 30 grid, 5 labels, noisy unaries around a blocky ground truth.
  const int w = 40, h = 30, L = 5;
  CrfEnergy energy(w * h, L);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int truth = (x / 10 + y / 10) % L;
      for (int l = 0; l < L; ++l) energy.SetUnary(y * w + x, l, (l == truth ? 0.0f : 0.6f) + unit(rng));
      if (x + 1 < w) energy.AddEdge(y * w + x, y * w + x + 1, 0.5f);
      if (y + 1 < h) energy.AddEdge(y * w + x, (y + 1) * w + x, 0.5f);
    }
  std::vector<CrfLabel> labels, icm_labels;
  CrfSolverSummary summary, icm;
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, AlphaExpansionOptions(), &labels, &summary).ok());
  ASSERT_TRUE(MinimizeWithIcm(energy, IcmOptions(), &icm_labels, &icm).ok());
  EXPECT_LT(summary.final_energy, icm.final_energy);
  EXPECT_LT(summary.final_energy, summary.initial_energy);
  ExpectMonotone(summary, "grid");
  int correct = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) correct += labels[y * w + x] == (x / 10 + y / 10) % L;
  EXPECT_GT(correct, 0.95 * w * h);
}

// Above 2^15 edges the moves are built on both cores (the node terms, the edges, the terminal capacities and
// the switching nodes in fixed ranges); the result does not depend on the threads: the same labels and the
// same energy after every expansion, bit for bit, on one thread and on all. Every move's cut also matches its
// energy change (the solver aborts otherwise), which checks the constants summed per range.
TEST(AlphaExpansion, LargeMovesGiveTheSameResultOnOneThreadAndOnAll) {
  const int w = 180, h = 120, L = 6;
  CrfEnergy energy(w * h, L);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int truth = (x / 15 + y / 20) % L;
      for (int l = 0; l < L; ++l) energy.SetUnary(y * w + x, l, (l == truth ? 0.0f : 0.5f) + unit(rng));
      if (x + 1 < w) energy.AddEdge(y * w + x, y * w + x + 1, 0.4f);
      if (y + 1 < h) energy.AddEdge(y * w + x, (y + 1) * w + x, 0.4f);
    }
  for (int c = 0; c < 4; ++c) {
    std::vector<int> members;
    for (int y = 30 * c; y < 30 * c + 20; ++y)
      for (int x = 40; x < 90; ++x) members.push_back(y * w + x);
    RobustPnParams p;
    p.gamma_max = 20;
    p.truncation_q = 200;
    energy.AddRobustPnClique(members, p);
  }
  ASSERT_GE(energy.edges().size(), size_t(1) << 15);
  AlphaExpansionOptions options;
  std::vector<CrfLabel> one_thread, all_threads;
  CrfSolverSummary s1, s2;
  tbb::task_arena one(1);
  one.execute([&] { ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &one_thread, &s1).ok()); });
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &all_threads, &s2).ok());
  EXPECT_EQ(one_thread, all_threads);
  EXPECT_EQ(s1.energy_per_expansion, s2.energy_per_expansion);
  EXPECT_EQ(s1.num_pruned_nodes, s2.num_pruned_nodes);
  EXPECT_GT(s2.num_pruned_nodes, 0);
  ExpectMonotone(s2, "large grid");
  EXPECT_LT(s2.final_energy, s2.initial_energy);
}

// MaxFlowGraph without PrepareConcurrentEdgeUpdates: RunAlphaExpansion then builds every move in one serial
// pass (edges, cliques, terminal capacities), the plain version of the parallel passes.
class SerialMovesGraph {
 public:
  int AddNodes(int count) { return graph_.AddNodes(count); }
  void ReserveEdges(size_t count) { graph_.ReserveEdges(count); }
  int AddEdge(int i, int j, double cap_ij, double cap_ji) { return graph_.AddEdge(i, j, cap_ij, cap_ji); }
  void ResetFlow() { graph_.ResetFlow(); }
  void SetEdgeCapacities(int edge, double cap_ij, double cap_ji) { graph_.SetEdgeCapacities(edge, cap_ij, cap_ji); }
  void SetTerminalCapacity(int node, double source_minus_sink) { graph_.SetTerminalCapacity(node, source_minus_sink); }
  double Solve() { return graph_.Solve(); }
  bool InSinkSegment(int node) const { return graph_.InSinkSegment(node); }
  size_t MemoryBytes() const { return graph_.MemoryBytes(); }

 private:
  MaxFlowGraph<double> graph_;
};

// The moves of a large problem with many overlapping Robust P^n cliques (their members shared between
// cliques and with the pairwise edges), built in parallel (edges in ranges, cliques one by one), give the
// labels, the energy after every expansion and the pruning of the plain serial construction.
TEST(AlphaExpansion, ParallelMovesWithManyCliquesEqualTheSerialMoves) {
  const int w = 200, h = 180, L = 7;
  std::mt19937_64 rng(33);
  CrfEnergy energy = NoisyBandGrid(w, h, L, 25, 18, 0.6f, 0.3f, &rng);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  // Blocks of 20 x 12 on a 10 x 6 stride: every pixel inside lies in up to four cliques; plus rows.
  for (int y0 = 0; y0 + 12 <= h; y0 += 6)
    for (int x0 = 0; x0 + 20 <= w; x0 += 10) {
      std::vector<int> members;
      std::vector<float> weights;
      for (int y = y0; y < y0 + 12; ++y)
        for (int x = x0; x < x0 + 20; ++x) {
          members.push_back(y * w + x);
          weights.push_back(0.5f + unit(rng));
        }
      RobustPnParams p;
      p.gamma_max = 4 + 4 * unit(rng);
      p.truncation_q = 40 + 60 * unit(rng);
      energy.AddRobustPnClique(members, p, weights);
    }
  for (int y = 0; y < h; y += 9) {
    std::vector<int> members;
    for (int x = 0; x < w; ++x) members.push_back(y * w + x);
    RobustPnParams p;
    p.gamma_max = 10;
    p.truncation_q = 60;
    energy.AddRobustPnClique(members, p);
  }
  ASSERT_GE(energy.edges().size(), size_t(1) << 15);  // Large enough for the parallel moves.
  ASSERT_GT(energy.num_cliques(), 500);
  AlphaExpansionOptions options;
  std::vector<CrfLabel> serial, parallel;
  CrfSolverSummary ss, sp;
  SerialMovesGraph serial_graph;
  ASSERT_TRUE(crf_internal::RunAlphaExpansion(energy, options, serial_graph, &serial, &ss).ok());
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &parallel, &sp).ok());
  EXPECT_EQ(serial, parallel);
  EXPECT_EQ(ss.energy_per_expansion, sp.energy_per_expansion);
  EXPECT_EQ(ss.energy_per_sweep, sp.energy_per_sweep);
  EXPECT_EQ(ss.num_pruned_nodes, sp.num_pruned_nodes);
  EXPECT_GT(sp.num_moves, 0);
  ExpectMonotone(sp, "cliques");
}

// A local re-solve: with `movable`, the unflagged nodes keep their labels, and the moves are those of the
// same energy in which every unflagged node's other labels cost 1e6 more (pruning then decides them "keep"):
// same labels, same energy after every expansion; on the parallel moves and on the serial ones.
TEST(AlphaExpansion, MovableNodesMoveAsIfTheOthersWereFixedByTheirUnaries) {
  const int w = 200, h = 180, L = 6, n = w * h;
  std::mt19937_64 rng(71);
  CrfEnergy energy = NoisyBandGrid(w, h, L, 30, 20, 0.5f, 0.35f, &rng);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int y0 = 0; y0 + 16 <= h; y0 += 16)
    for (int x0 = 0; x0 + 16 <= w; x0 += 24) {
      std::vector<int> members;
      for (int y = y0; y < y0 + 16; ++y)
        for (int x = x0; x < x0 + 16; ++x) members.push_back(y * w + x);
      RobustPnParams p;
      p.gamma_max = 3;
      p.truncation_q = 50;
      energy.AddRobustPnClique(members, p);
    }
  ASSERT_GE(energy.edges().size(), size_t(1) << 15);  // The parallel moves.
  // A start: one sweep of the plain solver. Then a local change of the unaries (a disc whose truth is label
  // 0), and the nodes within 6 pixels of it may move.
  AlphaExpansionOptions options;
  options.max_sweeps = 1;
  std::vector<CrfLabel> start;
  CrfSolverSummary s0;
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &start, &s0).ok());
  std::vector<uint8_t> movable(size_t(n), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double r = std::hypot(x - 70.0, y - 90.0);
      if (r < 25)
        for (int l = 0; l < L; ++l) energy.SetUnary(y * w + x, l, (l == 0 ? 0.0f : 0.9f) + unit(rng));
      movable[size_t(y * w + x)] = r < 31;
    }
  CrfEnergy fixed = energy;
  for (int i = 0; i < n; ++i)
    if (!movable[size_t(i)])
      for (int l = 0; l < L; ++l)
        if (l != start[size_t(i)]) fixed.SetUnary(i, l, energy.unary(i, l) + 1e6f);
  options.initial_labelling = InitialLabelling::kGiven;
  options.max_sweeps = 100;
  std::vector<CrfLabel> local = start, reference = start, serial = start;
  CrfSolverSummary sl, sr, ss;
  ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, options, &local, &sl, &movable).ok());
  ASSERT_TRUE(MinimizeWithAlphaExpansion(fixed, options, &reference, &sr).ok());
  SerialMovesGraph serial_graph;
  ASSERT_TRUE(crf_internal::RunAlphaExpansion(energy, options, serial_graph, &serial, &ss, &movable).ok());
  EXPECT_EQ(local, reference);
  EXPECT_EQ(local, serial);
  ASSERT_EQ(sl.energy_per_expansion.size(), sr.energy_per_expansion.size());
  for (size_t k = 0; k < sl.energy_per_expansion.size(); ++k)
    EXPECT_NEAR(sl.energy_per_expansion[k], sr.energy_per_expansion[k], 1e-9 * std::abs(sr.energy_per_expansion[k])) << k;
  EXPECT_EQ(sl.energy_per_expansion, ss.energy_per_expansion);
  ExpectMonotone(sl, "movable");
  int moved = 0;
  for (int i = 0; i < n; ++i) {
    if (!movable[size_t(i)]) {
      ASSERT_EQ(local[size_t(i)], start[size_t(i)]) << "node " << i << " is not movable";
    }
    moved += local[size_t(i)] != start[size_t(i)];
  }
  EXPECT_GT(moved, 500);  // The disc (about 1,960 nodes) did move to label 0 for the most part.
  EXPECT_LT(sl.final_energy, sl.initial_energy);
  // A flag vector of the wrong size is an input error.
  std::vector<uint8_t> short_flags(size_t(n - 1), 1);
  std::vector<CrfLabel> x = start;
  const Status st = MinimizeWithAlphaExpansion(energy, options, &x, &sl, &short_flags);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("movable"), std::string::npos) << st.message();
}

// min_sweep_improvement stops after the first sweep that gains less than that fraction of |E|; the moves
// until then are the classical run's, so its energies per sweep are a prefix of the classical run's.
// Potts grids with strong smoothing from an all-zero start need several sweeps.
TEST(AlphaExpansion, MinSweepImprovementStopsAtTheFirstSmallSweep) {
  int stopped_early = 0;
  const double t = 1e-3;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const int w = 30, h = 20, L = 4 + int(seed % 4);
    CrfEnergy energy(w * h, L);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const float potts = 0.3f + 0.1f * float(seed % 5);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        for (int l = 0; l < L; ++l) energy.SetUnary(y * w + x, l, unit(rng));
        if (x + 1 < w) energy.AddEdge(y * w + x, y * w + x + 1, potts);
        if (y + 1 < h) energy.AddEdge(y * w + x, (y + 1) * w + x, potts);
      }
    AlphaExpansionOptions full;
    full.initial_labelling = InitialLabelling::kGiven;
    AlphaExpansionOptions early = full;
    early.min_sweep_improvement = t;
    std::vector<CrfLabel> a(size_t(w * h), 0), b(size_t(w * h), 0);
    CrfSolverSummary sa, sb;
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, full, &a, &sa).ok());
    ASSERT_TRUE(MinimizeWithAlphaExpansion(energy, early, &b, &sb).ok());
    ExpectMonotone(sb, "seed " + std::to_string(seed));
    ASSERT_LE(sb.num_sweeps, sa.num_sweeps);
    for (int k = 0; k < sb.num_sweeps; ++k) EXPECT_DOUBLE_EQ(sb.energy_per_sweep[size_t(k)], sa.energy_per_sweep[size_t(k)]) << seed;
    // Every sweep but the last gained at least t |E|; the last gained less, or moved nothing.
    double before = sb.initial_energy;
    for (int k = 0; k + 1 < sb.num_sweeps; ++k) {
      EXPECT_GE(before - sb.energy_per_sweep[size_t(k)], t * std::abs(before)) << seed << " sweep " << k;
      before = sb.energy_per_sweep[size_t(k)];
    }
    EXPECT_TRUE(sb.converged || before - sb.final_energy < t * std::abs(before)) << seed;
    // Stopping early costs little: within 0.5% of the classical run's energy here.
    EXPECT_LE(sb.final_energy, sa.final_energy + 5e-3 * std::abs(sa.final_energy)) << seed;
    stopped_early += sb.num_sweeps < sa.num_sweeps;
  }
  std::printf("min_sweep_improvement %g stopped %d of 20 runs before the classical rule\n", t, stopped_early);
  EXPECT_GT(stopped_early, 0);  // The rule does act on these problems.
}

}  // namespace
}  // namespace semvox
