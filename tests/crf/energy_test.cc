#include "crf/energy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace semvox {
namespace {

CrfEnergy ThreeNodeChain() {
  // Nodes 0 - 1 - 2, 3 labels.
  CrfEnergy energy(3, 3);
  const float u[3][3] = {{0.0f, 1.0f, 2.0f}, {0.5f, 0.2f, 0.9f}, {3.0f, 0.0f, 0.1f}};
  for (int i = 0; i < 3; ++i) energy.SetUnaries(i, u[i]);
  energy.AddEdge(0, 1, 2.0f);  // Potts.
  const int linear = energy.AddCompatibilityModel({0, 1, 2, 1, 0, 1, 2, 1, 0});
  energy.AddEdge(1, 2, 0.5f, linear);
  return energy;
}

TEST(CrfEnergy, EvaluateSumsUnaryPairwiseAndHigherOrderParts) {
  CrfEnergy energy = ThreeNodeChain();
  RobustPnParams p;
  p.gamma_max = 4;
  p.truncation_q = 1.5f;  // W = 3.
  p.gamma = {0.0f, 1.0f, 2.0f};
  energy.AddRobustPnClique({0, 1, 2}, p);
  const std::vector<CrfLabel> x{0, 1, 2};
  EXPECT_NEAR(energy.UnaryEnergy(x), 0.0 + 0.2 + 0.1, 1e-6);  // Float unaries.
  EXPECT_NEAR(energy.PairwiseEnergy(x), 2.0 * 1 + 0.5 * 1, 1e-6);
  // Every label has 2 disagreeing nodes: min(4, 0 + 4/1.5*2, 1 + 3/1.5*2, 2 + 2/1.5*2) = min(4, 5.33, 5, 4.67).
  EXPECT_NEAR(energy.HigherOrderEnergy(x), 4.0, 1e-6);
  EXPECT_NEAR(energy.Evaluate(x), 0.3 + 2.5 + 4.0, 1e-6);
  const std::vector<CrfLabel> same{1, 1, 1};
  EXPECT_NEAR(energy.HigherOrderEnergy(same), 1.0, 1e-6);  // gamma_1, nobody disagrees.
}

TEST(CrfEnergy, UnaryArgminTakesTheLowestLabelOnTies) {
  CrfEnergy energy(2, 3);
  energy.SetUnaries(0, std::vector<float>{1.0f, 0.5f, 0.5f});
  energy.SetUnaries(1, std::vector<float>{0.0f, 0.0f, 0.0f});
  EXPECT_EQ(energy.UnaryArgmin(), (std::vector<CrfLabel>{1, 0}));
  EXPECT_FLOAT_EQ(energy.unary(0, 2), 0.5f);
  EXPECT_FLOAT_EQ(energy.unary_plane(1)[0], 0.5f);  // Label-major storage.
}

TEST(CrfEnergy, IsMetricRecognisesPottsLinearAndNonMetricModels) {
  CrfEnergy energy(2, 3);
  const int linear = energy.AddCompatibilityModel({0, 1, 2, 1, 0, 1, 2, 1, 0});
  const int squared = energy.AddCompatibilityModel({0, 1, 4, 1, 0, 1, 4, 1, 0});  // Violates the triangle inequality.
  const int asymmetric = energy.AddCompatibilityModel({0, 1, 1, 2, 0, 1, 1, 1, 0});
  EXPECT_TRUE(energy.IsMetric(CrfEnergy::kPottsModel));
  EXPECT_TRUE(energy.IsMetric(linear));
  EXPECT_FALSE(energy.IsMetric(squared));
  EXPECT_FALSE(energy.IsMetric(asymmetric));
}

TEST(CrfEnergy, CheckNamesNonFiniteUnariesAndNegativeWeights) {
  std::string error;
  {
    CrfEnergy energy(2, 2);
    energy.SetUnary(1, 1, std::numeric_limits<float>::quiet_NaN());
    EXPECT_FALSE(energy.Check(&error));
    EXPECT_NE(error.find("unary(node 1, label 1)"), std::string::npos) << error;
  }
  {
    CrfEnergy energy(2, 2);
    energy.AddEdge(0, 1, -1.0f);
    EXPECT_FALSE(energy.Check(&error));
    EXPECT_NE(error.find("edge 0 weight = -1"), std::string::npos) << error;
  }
  EXPECT_TRUE(ThreeNodeChain().Check(&error));
}

TEST(CrfEnergy, IncidenceListsEveryEdgeAndCliqueOfANode) {
  CrfEnergy energy = ThreeNodeChain();
  RobustPnParams p;
  energy.AddRobustPnClique({1, 2}, p);
  const NodeIncidence edges = energy.EdgeIncidence();
  EXPECT_EQ(edges.Of(0).size(), 1u);
  EXPECT_EQ(edges.Of(1).size(), 2u);
  const NodeIncidence cliques = energy.CliqueIncidence();
  EXPECT_EQ(cliques.Of(0).size(), 0u);
  EXPECT_EQ(cliques.Of(2).size(), 1u);
}

}  // namespace
}  // namespace semvox
