#include "perception/crf_learning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace semvox {
namespace {

// Random graphs: chains with extra edges, random unaries, labels, distances; every third edge has no g2.
std::vector<CrfTrainingGraph> RandomGraphs(int count, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(0.05, 1.0), d(0.0, 3.0);
  std::vector<CrfTrainingGraph> graphs;
  for (int k = 0; k < count; ++k) {
    CrfTrainingGraph g;
    g.num_labels = 3;
    const int n = 6 + k;
    for (int s = 0; s < n; ++s) {
      double p[3] = {u(*rng), u(*rng), u(*rng)};
      const double z = p[0] + p[1] + p[2];
      for (double v : p) g.log_probability.push_back(std::log(v / z));
      g.labels.push_back(s == 2 ? -1 : int((*rng)() % 3));
    }
    for (int s = 1; s < n; ++s) g.edges.push_back({s - 1, s, d(*rng), s % 3 == 0 ? -1.0 : d(*rng)});
    g.edges.push_back({0, n - 1, d(*rng), d(*rng)});
    graphs.push_back(std::move(g));
  }
  return graphs;
}

TEST(NegativeLogPseudoLikelihood, AnalyticGradientMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  const auto graphs = RandomGraphs(5, &rng);
  const double w[3] = {0.8, 1.3, 0.6};
  double g[3];
  NegativeLogPseudoLikelihood(graphs, w, g);
  constexpr double kStep = 1e-6;
  for (int k = 0; k < 3; ++k) {
    double wp[3] = {w[0], w[1], w[2]}, wm[3] = {w[0], w[1], w[2]};
    wp[k] += kStep;
    wm[k] -= kStep;
    const double numeric = (NegativeLogPseudoLikelihood(graphs, wp, nullptr) - NegativeLogPseudoLikelihood(graphs, wm, nullptr)) / (2 * kStep);
    EXPECT_NEAR(g[k], numeric, 1e-6) << "weight " << k;
  }
}

TEST(NegativeLogPseudoLikelihood, WithZeroPairwiseWeightsIsTheUnaryLogLoss) {
  std::mt19937 rng(12);
  const auto graphs = RandomGraphs(3, &rng);
  const double w[3] = {1, 0, 0};
  double expected = 0;
  int nodes = 0;
  for (const auto& g : graphs)
    for (size_t s = 0; s < g.labels.size(); ++s)
      if (g.labels[s] >= 0) {
        expected -= g.log_probability[s * 3 + size_t(g.labels[s])];
        ++nodes;
      }
  EXPECT_NEAR(NegativeLogPseudoLikelihood(graphs, w, nullptr), expected / nodes, 1e-12);
}

TEST(LearnCrfWeights, NeverEndsAboveTheInitialObjectiveAndRaisesAnInformativeColourWeight) {
  // Uninformative unaries; neighbours share their label exactly when their colours are close. The colour
  // pairwise explains the labels, so its weight must grow from a small start and the NLPL must fall.
  std::mt19937 rng(13);
  std::vector<CrfTrainingGraph> graphs;
  for (int k = 0; k < 20; ++k) {
    CrfTrainingGraph g;
    g.num_labels = 2;
    const int n = 12;
    int label = 0;
    for (int s = 0; s < n; ++s) {
      if (s > 0 && rng() % 4 == 0) label = 1 - label;
      g.labels.push_back(label);
      g.log_probability.push_back(std::log(0.5));
      g.log_probability.push_back(std::log(0.5));
    }
    for (int s = 1; s < n; ++s) g.edges.push_back({s - 1, s, g.labels[size_t(s)] == g.labels[size_t(s - 1)] ? 0.05 : 4.0, -1});
    graphs.push_back(std::move(g));
  }
  ViewCrfOptions initial;
  initial.colour_weight = 0.1;
  CrfLearningSummary summary;
  Result<ViewCrfOptions> learned = LearnCrfWeights(graphs, initial, CrfLearningOptions{}, &summary);
  ASSERT_TRUE(learned.ok()) << learned.status().message();
  EXPECT_LE(summary.final_nlpl, summary.initial_nlpl);
  EXPECT_GT(learned->colour_weight, 1.0);
  EXPECT_EQ(summary.nodes, 20 * 12);
}

TEST(LearnCrfWeights, RejectsEmptyInputAndBadOptions) {
  EXPECT_FALSE(LearnCrfWeights({}, ViewCrfOptions{}, CrfLearningOptions{}).ok());
  CrfLearningOptions bad;
  bad.max_iterations = 0;
  std::mt19937 rng(14);
  const Result<ViewCrfOptions> r = LearnCrfWeights(RandomGraphs(1, &rng), ViewCrfOptions{}, bad);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("max_iterations = 0"), std::string::npos);
}

}  // namespace
}  // namespace semvox
