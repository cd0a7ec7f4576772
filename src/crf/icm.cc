// Iterated conditional modes over a CrfEnergy: the baseline alpha-expansion is compared against.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/log.h"
#include "crf/solvers.h"

namespace semvox {

Status MinimizeWithIcm(const CrfEnergy& energy, const IcmOptions& options, std::vector<CrfLabel>* labels_out,
                       CrfSolverSummary* summary) {
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("IcmOptions: " + error);
  if (!energy.Check(&error)) return Status::InvalidInput("CrfEnergy: " + error);
  SEMVOX_RETURN_IF_ERROR(InitializeLabels(energy, options.initial_labelling, labels_out));
  std::vector<CrfLabel>& labels = *labels_out;
  *summary = CrfSolverSummary();
  summary->solver = "icm";

  const int N = energy.num_nodes();
  const int L = energy.num_labels();
  const int C = energy.num_cliques();
  const auto& edges = energy.edges();
  const NodeIncidence edge_incidence = energy.EdgeIncidence();
  const NodeIncidence clique_incidence = energy.CliqueIncidence();
  // Weight per label of every clique, kept up to date.
  std::vector<double> clique_weight(static_cast<size_t>(C) * L, 0.0);
  for (int c = 0; c < C; ++c) {
    const auto nodes = energy.clique_nodes(c);
    const auto weights = energy.clique_weights(c);
    for (size_t k = 0; k < nodes.size(); ++k) clique_weight[static_cast<size_t>(c) * L + labels[nodes[k]]] += weights[k];
  }
  // Weight of node i inside clique c (looked up per visit; cliques are sets, a node appears once).
  auto weight_in = [&](int c, int i) {
    const auto nodes = energy.clique_nodes(c);
    const auto weights = energy.clique_weights(c);
    double w = 0;
    for (size_t k = 0; k < nodes.size(); ++k) {
      if (nodes[k] == i) w += weights[k];
    }
    return w;
  };

  double current = energy.Evaluate(labels);
  summary->initial_energy = current;
  std::vector<double> cost(L);
  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    int64_t changes = 0;
    for (int i = 0; i < N; ++i) {
      const CrfLabel old = labels[i];
      for (CrfLabel l = 0; l < L; ++l) cost[l] = energy.unary(i, l);
      for (int e : edge_incidence.Of(i)) {
        const CrfEnergy::Edge& edge = edges[e];
        if (edge.i == i) {
          for (CrfLabel l = 0; l < L; ++l) cost[l] += energy.EdgeCost(edge, l, labels[edge.j]);
        } else {
          for (CrfLabel l = 0; l < L; ++l) cost[l] += energy.EdgeCost(edge, labels[edge.i], l);
        }
      }
      for (int c : clique_incidence.Of(i)) {
        std::span<double> weight(clique_weight.data() + static_cast<size_t>(c) * L, L);
        const double w = weight_in(c, i);
        weight[old] -= w;
        for (CrfLabel l = 0; l < L; ++l) {
          weight[l] += w;
          cost[l] += energy.CliquePotentialFromWeights(c, weight);
          weight[l] -= w;
        }
        weight[old] += w;
      }
      CrfLabel best = old;
      for (CrfLabel l = 0; l < L; ++l) {
        if (cost[l] < cost[best]) best = l;
      }
      if (best == old || !(cost[best] < cost[old] - 1e-12 * (1.0 + std::abs(cost[old])))) continue;
      current += cost[best] - cost[old];
      for (int c : clique_incidence.Of(i)) {
        const double w = weight_in(c, i);
        clique_weight[static_cast<size_t>(c) * L + old] -= w;
        clique_weight[static_cast<size_t>(c) * L + best] += w;
      }
      labels[i] = best;
      ++changes;
    }
    const double exact = energy.Evaluate(labels);
    const double previous = summary->energy_per_sweep.empty() ? summary->initial_energy : summary->energy_per_sweep.back();
    if (exact > previous + 1e-9 * (1.0 + std::abs(previous))) {
      std::fprintf(stderr, "semvox: ICM invariant violated: energy rose from %.17g to %.17g\n", previous, exact);
      std::abort();
    }
    current = exact;
    summary->energy_per_sweep.push_back(exact);
    summary->num_sweeps = sweep + 1;
    summary->num_moves += changes;
    SEMVOX_LOG(kDebug, "icm sweep " << sweep + 1 << ": E = " << exact << ", " << changes << " nodes changed");
    if (changes == 0) {
      summary->converged = true;
      break;
    }
  }
  summary->final_energy = current;
  summary->seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  return Status::Ok();
}

}  // namespace semvox
