// Random CRF problems and brute-force minimisers for the crf tests.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "crf/energy.h"

namespace semvox::testing {

struct RandomEnergySpec {
  int num_nodes = 6;
  int num_labels = 3;
  double edge_probability = 0.4;
  int num_cliques = 0;
  bool metric_model = false;      // Add a metric compatibility model (truncated linear) and use it on some edges.
  bool nonmetric_model = false;   // Add an arbitrary non-negative model and use it on some edges.
  bool weighted_cliques = false;  // Random clique node weights instead of 1.
  bool negative_unaries = false;  // Unaries in [-1, 1) instead of [0, 1).
};

inline CrfEnergy MakeRandomEnergy(const RandomEnergySpec& spec, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const int N = spec.num_nodes, L = spec.num_labels;
  CrfEnergy energy(N, L);
  for (int i = 0; i < N; ++i) {
    for (int l = 0; l < L; ++l) energy.SetUnary(i, l, spec.negative_unaries ? 2 * unit(rng) - 1 : unit(rng));
  }
  std::vector<int> models{CrfEnergy::kPottsModel};
  if (spec.metric_model) {
    std::vector<float> m(L * L);
    const float cap = 1.0f + unit(rng) * L;
    for (int a = 0; a < L; ++a)
      for (int b = 0; b < L; ++b) m[a * L + b] = std::min<float>(std::abs(a - b), cap);
    models.push_back(energy.AddCompatibilityModel(m));
  }
  if (spec.nonmetric_model) {
    std::vector<float> m(L * L);
    for (float& v : m) v = unit(rng);
    models.push_back(energy.AddCompatibilityModel(m));
  }
  for (int i = 0; i < N; ++i) {
    for (int j = i + 1; j < N; ++j) {
      if (unit(rng) < spec.edge_probability) {
        const int model = models[rng() % models.size()];
        if (rng() % 2) {
          energy.AddEdge(i, j, unit(rng), model);
        } else {
          energy.AddEdge(j, i, unit(rng), model);
        }
      }
    }
  }
  for (int c = 0; c < spec.num_cliques && N >= 2; ++c) {
    std::vector<int> nodes;
    for (int i = 0; i < N; ++i) {
      if (unit(rng) < 0.5) nodes.push_back(i);
    }
    if (nodes.size() < 2) nodes = {0, N - 1};
    std::vector<float> weights;
    double W = static_cast<double>(nodes.size());
    if (spec.weighted_cliques) {
      W = 0;
      for (size_t k = 0; k < nodes.size(); ++k) {
        weights.push_back(0.2f + unit(rng));
        W += weights.back();
      }
    }
    RobustPnParams params;
    params.gamma_max = 0.5f + 2 * unit(rng);
    params.truncation_q = static_cast<float>(std::max(1e-3, W / 2 * (0.1 + 0.89 * unit(rng))));
    for (int l = 0; l < L; ++l) params.gamma.push_back(params.gamma_max * unit(rng) * 0.8f);
    energy.AddRobustPnClique(nodes, params, weights);
  }
  return energy;
}

// Calls f for every labelling in [0, L)^N (N small).
inline void ForEachLabelling(int N, int L, const std::function<void(const std::vector<CrfLabel>&)>& f) {
  std::vector<CrfLabel> x(N, 0);
  for (;;) {
    f(x);
    int k = 0;
    while (k < N && ++x[k] == L) x[k++] = 0;
    if (k == N) return;
  }
}

inline double BruteForceMinimum(const CrfEnergy& energy, std::vector<CrfLabel>* argmin = nullptr) {
  double best = std::numeric_limits<double>::infinity();
  ForEachLabelling(energy.num_nodes(), energy.num_labels(), [&](const std::vector<CrfLabel>& x) {
    const double e = energy.Evaluate(x);
    if (e < best) {
      best = e;
      if (argmin) *argmin = x;
    }
  });
  return best;
}

}  // namespace semvox::testing
