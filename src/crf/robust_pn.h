// The alpha-expansion move of a Robust P^n clique as a graph-representable binary energy with two
// auxiliary nodes (Kohli, Ladicky & Torr, IJCV 2009, Sec. 5, "the expansion move for Robust P^n").
//
// Move variables t_i in {0 = keep x_i, 1 = take alpha} for the clique's nodes with x_i != alpha (nodes
// already at alpha are fixed). Let W_l be the clique weight with label l, k_l = (gamma_max - gamma_l) / Q.
// After the move only two labels can be below gamma_max (because 2Q <= W): alpha, and the current
// "dominant" label d != alpha with W - W_d < Q, if any. Hence
//
//   psi(t) = gamma_max + k_alpha (min(Q, S) - Q) + k_d (min(Q', T) - Q'),
//   S  = sum_{i: x_i != alpha} w_i [t_i = 0]    (weight that stays off alpha),
//   T  = sum_{i: x_i = d} w_i [t_i = 1]          (weight that leaves d),      Q' = Q - (W - W_d) > 0,
//
// and each min(., .) is one auxiliary binary node with submodular pairwise terms:
//   min(Q, S)  = min_z  Q [z = 0] + sum_i w_i [t_i = 0][z = 1]    (arcs i -> z, capacity k_alpha w_i),
//   min(Q', T) = min_y  Q' [y = 1] + sum_i w_i [y = 0][t_i = 1]   (arcs y -> i, capacity k_d w_i).
// Graph convention: 0 = source side, 1 = sink side.
#pragma once

#include <span>
#include <vector>

#include "crf/energy.h"

namespace semvox {

struct RobustPnMove {
  double constant = 0;        // gamma_max - k_alpha Q - k_d Q'.
  double alpha_slope = 0;     // k_alpha: capacity per unit weight of arcs i -> z (0 = no z term).
  double alpha_aux_cost = 0;  // k_alpha Q, paid when z is on the source side.
  CrfLabel dominant = -1;     // d, or -1 when there is none (or k_d = 0).
  double dominant_slope = 0;  // k_d: capacity per unit weight of arcs y -> i for nodes with x_i = d.
  double dominant_aux_cost = 0;  // k_d Q', paid when y is on the sink side.
};

// Plans the move of clique c from `labels` towards `alpha`. `scratch` is resized to L and left zeroed.
RobustPnMove PlanRobustPnMove(const CrfEnergy& energy, int clique, std::span<const CrfLabel> labels,
                              CrfLabel alpha, std::vector<double>* scratch);

// The move energy of the plan for given move variables (take_alpha[k] for the clique's k-th node; ignored
// for nodes already at alpha) and auxiliary values z, y in {0, 1}. Minimising over z and y gives psi_c
// of the labelling after the move; tests use this to check the construction.
double RobustPnMoveEnergy(const CrfEnergy& energy, int clique, std::span<const CrfLabel> labels,
                          CrfLabel alpha, const RobustPnMove& move, std::span<const bool> take_alpha,
                          bool z, bool y);

}  // namespace semvox
