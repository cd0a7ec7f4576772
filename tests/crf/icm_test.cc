#include <gtest/gtest.h>

#include <random>

#include "crf/energy.h"
#include "crf/solvers.h"
#include "tests/crf/crf_test_util.h"

namespace semvox {
namespace {

TEST(Icm, NeverIncreasesEnergyAndEndsInASingleNodeLocalMinimum) {
  for (uint64_t seed = 0; seed < 200; ++seed) {
    testing::RandomEnergySpec spec;
    spec.num_nodes = 5 + static_cast<int>(seed % 30);
    spec.num_labels = 2 + static_cast<int>(seed % 4);
    spec.edge_probability = 0.15;
    spec.num_cliques = static_cast<int>(seed % 3);
    spec.metric_model = seed % 2 == 0;
    spec.nonmetric_model = seed % 3 == 0;
    spec.weighted_cliques = seed % 4 == 0;
    const CrfEnergy energy = testing::MakeRandomEnergy(spec, 500 + seed);
    IcmOptions options;
    options.initial_labelling = seed % 2 ? InitialLabelling::kAllZero : InitialLabelling::kUnaryArgmin;
    std::vector<CrfLabel> labels;
    CrfSolverSummary summary;
    ASSERT_TRUE(MinimizeWithIcm(energy, options, &labels, &summary).ok());
    double previous = summary.initial_energy;
    for (double e : summary.energy_per_sweep) {
      ASSERT_LE(e, previous + 1e-9 * (1 + std::abs(previous))) << "seed " << seed;
      previous = e;
    }
    ASSERT_TRUE(summary.converged);
    const double e = energy.Evaluate(labels);
    EXPECT_NEAR(e, summary.final_energy, 1e-9 * (1 + std::abs(e)));
    for (int i = 0; i < spec.num_nodes; ++i) {
      std::vector<CrfLabel> changed = labels;
      for (CrfLabel l = 0; l < spec.num_labels; ++l) {
        changed[i] = l;
        ASSERT_GE(energy.Evaluate(changed), e - 1e-9 * (1 + std::abs(e))) << "seed " << seed << " node " << i;
      }
    }
  }
}

TEST(Icm, BadOptionsNameTheField) {
  CrfEnergy energy(2, 2);
  IcmOptions options;
  options.max_sweeps = -1;
  std::vector<CrfLabel> labels;
  CrfSolverSummary summary;
  const Status st = MinimizeWithIcm(energy, options, &labels, &summary);
  EXPECT_EQ(st.code(), StatusCode::kInvalidInput);
  EXPECT_NE(st.message().find("max_sweeps = -1"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace semvox
