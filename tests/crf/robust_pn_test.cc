#include "crf/robust_pn.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <random>

#include "crf/energy.h"
#include "tests/crf/crf_test_util.h"

namespace semvox {
namespace {

// Robust P^n straight from Kohli et al. 2009, Eq. 9-10, independent of CrfEnergy's implementation.
double DirectRobustPn(const std::vector<CrfLabel>& x, const std::vector<float>& w, const std::vector<float>& gamma,
                      double gamma_max, double q) {
  double best = gamma_max;
  for (size_t l = 0; l < gamma.size(); ++l) {
    double disagreeing = 0;
    for (size_t k = 0; k < x.size(); ++k) {
      if (x[k] != static_cast<CrfLabel>(l)) disagreeing += w[k];
    }
    best = std::min(best, gamma[l] + (gamma_max - gamma[l]) / q * disagreeing);
  }
  return best;
}

TEST(RobustPn, PotentialMatchesDirectEvaluation) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 2 + trial % 5, L = 2 + trial % 3;
    CrfEnergy energy(n, L);
    std::vector<int> nodes(n);
    std::vector<float> w(n);
    double W = 0;
    for (int k = 0; k < n; ++k) {
      nodes[k] = k;
      w[k] = trial % 2 ? 0.3f + unit(rng) : 1.0f;
      W += w[k];
    }
    RobustPnParams p;
    p.gamma_max = 1 + unit(rng);
    p.truncation_q = static_cast<float>(W / 2 * (0.05 + 0.9 * unit(rng)));
    for (int l = 0; l < L; ++l) p.gamma.push_back(unit(rng) * p.gamma_max);
    energy.AddRobustPnClique(nodes, p, w);
    ASSERT_TRUE(energy.Check(nullptr));
    testing::ForEachLabelling(n, L, [&](const std::vector<CrfLabel>& x) {
      EXPECT_NEAR(energy.CliquePotential(0, x), DirectRobustPn(x, w, p.gamma, p.gamma_max, p.truncation_q), 1e-6);
    });
  }
}

// For every labelling x of small cliques, every alpha and every expansion move t: minimising the
// two-auxiliary-node construction over z and y gives psi of the labelling after the move.
TEST(RobustPn, ExpansionMoveConstructionMatchesDirectEvaluation) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int64_t checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 2 + trial % 5;  // Clique sizes 2..6.
    const int L = 2 + (trial / 5) % 3;
    CrfEnergy energy(n, L);
    std::vector<int> nodes(n);
    std::vector<float> w;
    double W = n;
    for (int k = 0; k < n; ++k) nodes[k] = k;
    if (trial % 3 == 2) {
      W = 0;
      for (int k = 0; k < n; ++k) {
        w.push_back(0.25f + unit(rng));
        W += w.back();
      }
    }
    RobustPnParams p;
    p.gamma_max = 0.5f + 2 * unit(rng);
    // Q from tiny to exactly W / 2 (the largest allowed).
    p.truncation_q = trial % 4 == 0 ? static_cast<float>(W / 2) : static_cast<float>(W / 2 * (0.05 + 0.9 * unit(rng)));
    for (int l = 0; l < L; ++l) p.gamma.push_back(trial % 7 == 0 && l == 0 ? p.gamma_max : unit(rng) * p.gamma_max);
    energy.AddRobustPnClique(nodes, p, w);
    ASSERT_TRUE(energy.Check(nullptr));
    std::vector<double> scratch;
    testing::ForEachLabelling(n, L, [&](const std::vector<CrfLabel>& x) {
      for (CrfLabel alpha = 0; alpha < L; ++alpha) {
        const RobustPnMove move = PlanRobustPnMove(energy, 0, x, alpha, &scratch);
        for (uint32_t mask = 0; mask < (1u << n); ++mask) {
          std::vector<bool> take(n);
          std::vector<CrfLabel> after = x;
          for (int k = 0; k < n; ++k) {
            take[k] = (mask >> k) & 1;
            if (take[k]) after[k] = alpha;
          }
          // std::vector<bool> has no span; copy into a plain array.
          std::unique_ptr<bool[]> t(new bool[n]);
          for (int k = 0; k < n; ++k) t[k] = take[k];
          double best = std::numeric_limits<double>::infinity();
          for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 2; ++y)
              best = std::min(best, RobustPnMoveEnergy(energy, 0, x, alpha, move, {t.get(), static_cast<size_t>(n)}, z, y));
          ASSERT_NEAR(best, energy.CliquePotential(0, after), 1e-5)
              << "trial " << trial << " alpha " << alpha << " mask " << mask;
          ++checked;
        }
      }
    });
  }
  EXPECT_GT(checked, 10000);
}

TEST(RobustPn, CheckNamesTheTruncationWhenQExceedsHalfTheClique) {
  CrfEnergy energy(4, 2);
  RobustPnParams p;
  p.truncation_q = 3;  // W = 4.
  energy.AddRobustPnClique({0, 1, 2, 3}, p);
  std::string error;
  EXPECT_FALSE(energy.Check(&error));
  EXPECT_NE(error.find("truncation_q = 3"), std::string::npos) << error;
  EXPECT_NE(error.find("Violated constraint"), std::string::npos) << error;
}

TEST(RobustPn, CheckNamesGammaAboveGammaMax) {
  CrfEnergy energy(4, 2);
  RobustPnParams p;
  p.gamma_max = 1;
  p.gamma = {0.5f, 2.0f};
  energy.AddRobustPnClique({0, 1, 2, 3}, p);
  std::string error;
  EXPECT_FALSE(energy.Check(&error));
  EXPECT_NE(error.find("gamma[1] = 2"), std::string::npos) << error;
}

}  // namespace
}  // namespace semvox
