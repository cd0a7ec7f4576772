#include "crf/robust_pn.h"

#include <algorithm>

namespace semvox {

RobustPnMove PlanRobustPnMove(const CrfEnergy& energy, int clique, std::span<const CrfLabel> labels,
                              CrfLabel alpha, std::vector<double>* scratch) {
  const int L = energy.num_labels();
  std::vector<double>& weight = *scratch;
  if (static_cast<int>(weight.size()) != L) weight.assign(L, 0.0);
  const auto nodes = energy.clique_nodes(clique);
  const auto weights = energy.clique_weights(clique);
  for (size_t k = 0; k < nodes.size(); ++k) weight[labels[nodes[k]]] += weights[k];

  const double W = energy.clique_total_weight(clique);
  const double Q = energy.clique_truncation(clique);
  RobustPnMove move;
  move.alpha_slope = energy.clique_slope(clique, alpha);
  move.alpha_aux_cost = move.alpha_slope * Q;
  // The dominant label: the heaviest label other than alpha, if its disagreeing weight is below Q.
  CrfLabel d = -1;
  for (size_t k = 0; k < nodes.size(); ++k) {
    const CrfLabel l = labels[nodes[k]];
    if (l != alpha && (d < 0 || weight[l] > weight[d])) d = l;
  }
  if (d >= 0 && W - weight[d] < Q) {
    const double slope = energy.clique_slope(clique, d);
    if (slope > 0) {
      move.dominant = d;
      move.dominant_slope = slope;
      move.dominant_aux_cost = slope * (Q - (W - weight[d]));
    }
  }
  move.constant = energy.clique_gamma_max(clique) - move.alpha_aux_cost - move.dominant_aux_cost;
  for (size_t k = 0; k < nodes.size(); ++k) weight[labels[nodes[k]]] = 0.0;
  return move;
}

double RobustPnMoveEnergy(const CrfEnergy& energy, int clique, std::span<const CrfLabel> labels,
                          CrfLabel alpha, const RobustPnMove& move, std::span<const bool> take_alpha,
                          bool z, bool y) {
  const auto nodes = energy.clique_nodes(clique);
  const auto weights = energy.clique_weights(clique);
  double e = move.constant;
  if (!z) e += move.alpha_aux_cost;
  if (y && move.dominant >= 0) e += move.dominant_aux_cost;
  for (size_t k = 0; k < nodes.size(); ++k) {
    const CrfLabel x = labels[nodes[k]];
    if (x == alpha) continue;
    const bool t = take_alpha[k];
    if (!t && z) e += move.alpha_slope * weights[k];
    if (x == move.dominant && !y && t) e += move.dominant_slope * weights[k];
  }
  return e;
}

}  // namespace semvox
