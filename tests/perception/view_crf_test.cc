#include "perception/view_crf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace semvox {
namespace {

// Six superpixels: 0-3 with depth on a line at x = 0, 1, 3, 6; 4 and 5 without depth. Image adjacency:
// 0-1, 1-2, 2-3, 3-4, 2-4, 4-5, 0-5.
ViewObservations HandBuiltObservations() {
  ViewObservations obs;
  obs.superpixels.resize(6);
  const double xs[4] = {0, 1, 3, 6};
  for (int s = 0; s < 6; ++s) {
    auto& o = obs.superpixels[size_t(s)];
    o.lab_mean = Eigen::Vector3f(50.0f + 10.0f * float(s), 0, 0);
    if (s < 4) {
      o.has_depth = true;
      o.centroid_world = {xs[s], 0, 0};
    }
  }
  obs.image_adjacency = {{0, 1}, {0, 5}, {1, 2}, {2, 3}, {2, 4}, {3, 4}, {4, 5}};
  return obs;
}

bool HasEdge(const ViewGraph& g, int i, int j, ViewEdgeKind kind) {
  return std::any_of(g.edges.begin(), g.edges.end(), [&](const ViewGraph::Edge& e) {
    return e.kind == kind && std::min(e.i, e.j) == std::min(i, j) && std::max(e.i, e.j) == std::max(i, j);
  });
}

TEST(ViewGraph, TreeIsTheMstOverDepthCentroidsAndLeavesTheOthersAlone) {
  const ViewGraph g = BuildTreeGraph(HandBuiltObservations());
  EXPECT_EQ(g.num_nodes, 6);
  ASSERT_EQ(g.edges.size(), 3u);
  EXPECT_TRUE(HasEdge(g, 0, 1, ViewEdgeKind::kDepth));
  EXPECT_TRUE(HasEdge(g, 1, 2, ViewEdgeKind::kDepth));
  EXPECT_TRUE(HasEdge(g, 2, 3, ViewEdgeKind::kDepth));
}

TEST(ViewGraph, UnionAddsTheColourMstOverEdgesThroughSuperpixelsWithoutDepth) {
  const ViewGraph g = BuildUnionCoverageGraph(HandBuiltObservations());
  // Candidates touching 4 or 5 and their LAB distances: 3-4 10, 4-5 10, 2-4 20, 0-5 50. Kruskal over these
  // alone (the 3D tree is not seen) keeps all four: none closes a cycle among them. The union graph
  // then has loops through the 3D tree (0-1-2-4-5-0).
  EXPECT_EQ(g.edges.size(), 3u + 4u);
  EXPECT_TRUE(HasEdge(g, 3, 4, ViewEdgeKind::kImage));
  EXPECT_TRUE(HasEdge(g, 4, 5, ViewEdgeKind::kImage));
  EXPECT_TRUE(HasEdge(g, 2, 4, ViewEdgeKind::kImage));
  EXPECT_TRUE(HasEdge(g, 0, 5, ViewEdgeKind::kImage));
  EXPECT_FALSE(HasEdge(g, 0, 1, ViewEdgeKind::kImage));  // Both ends have depth: only the 3D tree joins them.
}

TEST(ViewGraph, ColourMstDropsTheHeavierEdgeOfACycleAmongSuperpixelsWithoutDepth) {
  ViewObservations obs;
  obs.superpixels.resize(3);  // None has depth: the union graph is the colour MST of the triangle.
  obs.superpixels[0].lab_mean = {0, 0, 0};
  obs.superpixels[1].lab_mean = {1, 0, 0};
  obs.superpixels[2].lab_mean = {3, 0, 0};
  obs.image_adjacency = {{0, 1}, {0, 2}, {1, 2}};
  const ViewGraph g = BuildUnionCoverageGraph(obs);
  ASSERT_EQ(g.edges.size(), 2u);
  EXPECT_TRUE(HasEdge(g, 0, 1, ViewEdgeKind::kImage));
  EXPECT_TRUE(HasEdge(g, 1, 2, ViewEdgeKind::kImage));
}

TEST(BuildViewCrf, PotentialsFollowEq3AndEq6) {
  const ViewObservations obs = HandBuiltObservations();
  const ViewGraph g = BuildTreeGraph(obs);
  const std::vector<std::vector<double>> p(6, {0.7, 0.2, 0.1});
  ViewCrfOptions options;
  options.unary_weight = 2.0;
  options.colour_weight = 1.5;
  Result<PairwiseModel> model = BuildViewCrf(obs, g, p, {}, false, options);
  ASSERT_TRUE(model.ok()) << model.status().message();
  EXPECT_NEAR(model->log_unary[1], 2.0 * std::log(0.2), 1e-12);
  const PairwiseModel::Edge& e = model->edges[0];  // 0-1: LAB distance 10, scaled 1.
  EXPECT_NEAR(e.log_pairwise[0], -1.5 * (1 - std::exp(-1.0)), 1e-12);   // Same label.
  EXPECT_NEAR(e.log_pairwise[1], -1.5 * std::exp(-1.0), 1e-12);         // Different labels.
  EXPECT_NEAR(e.log_pairwise[4], e.log_pairwise[0], 1e-15);
}

TEST(BuildViewCrf, UnionCrfUsesTheImageOnlyUnaryWithoutDepthAndG2OnDepthEdges) {
  const ViewObservations obs = HandBuiltObservations();
  const ViewGraph g = BuildUnionCoverageGraph(obs);
  const std::vector<std::vector<double>> f2(6, {0.9, 0.1}), f1(6, {0.3, 0.7});
  ViewCrfOptions options;
  options.colour_weight = 0;
  options.distance_weight = 1.0;
  options.distance_scale_m = 1.0;
  Result<PairwiseModel> model = BuildViewCrf(obs, g, f2, f1, true, options);
  ASSERT_TRUE(model.ok());
  EXPECT_NEAR(model->log_unary[0], std::log(0.9), 1e-12);      // Superpixel 0 has depth: f2.
  EXPECT_NEAR(model->log_unary[4 * 2], std::log(0.3), 1e-12);  // Superpixel 4 has none: f1.
  for (size_t k = 0; k < g.edges.size(); ++k) {
    const auto& e = model->edges[k];
    if (g.edges[k].kind == ViewEdgeKind::kImage) {
      EXPECT_EQ(e.log_pairwise[0], 0.0);  // Colour weight 0 and no g2 on image edges: exp(0) potentials.
      EXPECT_EQ(e.log_pairwise[1], -0.0);
    } else {
      const double d = (obs.superpixels[size_t(e.i)].centroid_world - obs.superpixels[size_t(e.j)].centroid_world).norm();
      EXPECT_NEAR(e.log_pairwise[0], -(1 - std::exp(-d)), 1e-12);
      EXPECT_NEAR(e.log_pairwise[1], -std::exp(-d), 1e-12);
    }
  }
  Marginals marg;
  LoopyBpSummary summary;
  ASSERT_TRUE(LoopyBeliefPropagation(*model, LoopyBpOptions{}, &marg, &summary).ok());
  EXPECT_TRUE(summary.converged);
}

TEST(BuildViewCrf, WithoutPairwiseWeightsTheMarginalsAreTheUnaries) {
  const ViewObservations obs = HandBuiltObservations();
  std::vector<std::vector<double>> p = {{0.6, 0.4}, {0.2, 0.8}, {0.5, 0.5}, {0.9, 0.1}, {0.3, 0.7}, {0.1, 0.9}};
  ViewCrfOptions options;
  options.colour_weight = 0;
  options.distance_weight = 0;
  Result<PairwiseModel> model = BuildViewCrf(obs, BuildTreeGraph(obs), p, {}, false, options);
  ASSERT_TRUE(model.ok());
  Marginals marg;
  ASSERT_TRUE(TreeSumProduct(*model, &marg).ok());
  for (int s = 0; s < 6; ++s)
    for (int l = 0; l < 2; ++l) EXPECT_NEAR(marg.at(s, l), p[size_t(s)][size_t(l)], 1e-12);
}

TEST(BuildViewCrf, RejectsZeroProbabilitiesAndMismatchedRows) {
  const ViewObservations obs = HandBuiltObservations();
  const ViewGraph g = BuildTreeGraph(obs);
  std::vector<std::vector<double>> p(6, {1.0, 0.0});
  Result<PairwiseModel> model = BuildViewCrf(obs, g, p, {}, false, {});
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.status().message().find("probability_floor"), std::string::npos);
  p.resize(5, {0.5, 0.5});
  EXPECT_FALSE(BuildViewCrf(obs, g, p, {}, false, {}).ok());
  ViewCrfOptions bad;
  bad.colour_scale_lab = 0;
  EXPECT_NE(BuildViewCrf(obs, g, std::vector<std::vector<double>>(6, {0.5, 0.5}), {}, false, bad).status().message().find("colour_scale_lab = 0"),
            std::string::npos);
}

TEST(PixelOutputs, EveryPixelTakesItsSuperpixelsRow) {
  Superpixels sp;
  sp.label = Image<int32_t>(3, 2, 1, 0);
  sp.label.at(2, 1) = 1;
  sp.count = 2;
  Marginals marg;
  marg.num_labels = 2;
  marg.p = {0.25, 0.75, 0.9, 0.1};
  const ImageF32 probs = PixelProbabilities(sp, marg);
  EXPECT_EQ(probs.channels, 2);
  EXPECT_FLOAT_EQ(probs.at(0, 0, 1), 0.75f);
  EXPECT_FLOAT_EQ(probs.at(2, 1, 0), 0.9f);
  const Image<int32_t> labels = PixelLabels(sp, DecodeMaxMarginals(marg));
  EXPECT_EQ(labels.at(1, 1), 1);
  EXPECT_EQ(labels.at(2, 1), 0);
}

}  // namespace
}  // namespace semvox
