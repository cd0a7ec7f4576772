// The alpha-expansion driver, templated on the max-flow graph so that the benchmark can run the same
// moves on another max-flow implementation (bench/crf_bench.cc runs it on Boost's
// boykov_kolmogorov_max_flow). Included by crf/alpha_expansion.cc and the benchmark only.
//
// Graph must provide: AddNodes(n), AddEdge(i, j, cap_ij, cap_ji) -> id (ids 0, 1, ...), ResetFlow(),
// SetEdgeCapacities(id, cap_ij, cap_ji), SetTerminalCapacity(node, source_minus_sink) (overwrites), Solve() -> flow, InSinkSegment(node), MemoryBytes(). Every move sets every edge and node.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

#include "core/log.h"
#include "crf/energy.h"
#include "crf/robust_pn.h"
#include "crf/solvers.h"

namespace semvox::crf_internal {

// Per-node state of one expansion move when pruning.
inline constexpr uint8_t kMoveFree = 0;     // Decided by the cut.
inline constexpr uint8_t kMoveKeep = 1;     // Keeps its label in every optimal move.
inline constexpr uint8_t kMoveSwitch = 2;   // Takes alpha in every optimal move.
inline constexpr uint8_t kMoveAtAlpha = 3;  // Already labelled alpha.

[[noreturn]] inline void ExpansionInvariantFailed(const std::string& what) {
  std::fprintf(stderr, "semvox: alpha-expansion invariant violated: %s\n", what.c_str());
  std::abort();
}

// Energy change when the nodes in `changed` (flag per node) move to alpha; exact, local.
inline double ExpansionEnergyChange(const CrfEnergy& energy, const NodeIncidence& edge_incidence,
                                    const NodeIncidence& clique_incidence,
                                    std::span<const CrfLabel> labels, std::span<const float> current_unary,
                                    const std::vector<int>& changed_nodes,
                                    const std::vector<uint8_t>& changed, CrfLabel alpha,
                                    std::vector<int>* clique_stamp, int stamp,
                                    std::vector<double>* old_weight, std::vector<double>* new_weight) {
  double delta = 0;
  const auto& edges = energy.edges();
  const float* plane = energy.unary_plane(alpha).data();
  for (int i : changed_nodes) {
    delta += static_cast<double>(plane[i]) - current_unary[i];
    for (int e : edge_incidence.Of(i)) {
      const CrfEnergy::Edge& edge = edges[e];
      const int other = edge.i == i ? edge.j : edge.i;
      if (changed[other] && other < i) continue;  // Counted from the other end.
      const CrfLabel ni = changed[edge.i] ? alpha : labels[edge.i];
      const CrfLabel nj = changed[edge.j] ? alpha : labels[edge.j];
      delta += static_cast<double>(energy.EdgeCost(edge, ni, nj)) - energy.EdgeCost(edge, labels[edge.i], labels[edge.j]);
    }
    for (int c : clique_incidence.Of(i)) {
      if ((*clique_stamp)[c] == stamp) continue;
      (*clique_stamp)[c] = stamp;
      const auto nodes = energy.clique_nodes(c);
      const auto weights = energy.clique_weights(c);
      for (size_t k = 0; k < nodes.size(); ++k) {
        const int v = nodes[k];
        (*old_weight)[labels[v]] += weights[k];
        (*new_weight)[changed[v] ? alpha : labels[v]] += weights[k];
      }
      delta += energy.CliquePotentialFromWeights(c, *new_weight) - energy.CliquePotentialFromWeights(c, *old_weight);
      std::fill(old_weight->begin(), old_weight->end(), 0.0);
      std::fill(new_weight->begin(), new_weight->end(), 0.0);
    }
  }
  return delta;
}

// `movable` (optional, one flag per node): nodes flagged 0 keep their labels; the moves are then built over
// the edges that touch a movable node only (see MinimizeWithAlphaExpansion).
template <typename Graph>
Status RunAlphaExpansion(const CrfEnergy& energy, const AlphaExpansionOptions& options, Graph& graph,
                         std::vector<CrfLabel>* labels_out, CrfSolverSummary* summary,
                         const std::vector<uint8_t>* movable = nullptr) {
  using Clock = std::chrono::steady_clock;
  const auto t_start = Clock::now();
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("AlphaExpansionOptions: " + error);
  if (!energy.Check(&error)) return Status::InvalidInput("CrfEnergy: " + error);
  SEMVOX_RETURN_IF_ERROR(InitializeLabels(energy, options.initial_labelling, labels_out));
  if (movable && movable->size() != size_t(energy.num_nodes()))
    return Status::InvalidInput("alpha-expansion: " + std::to_string(movable->size()) + " movable flags for " +
                                std::to_string(energy.num_nodes()) + " nodes");
  std::vector<CrfLabel>& labels = *labels_out;
  *summary = CrfSolverSummary();
  summary->solver = "alpha-expansion";

  const int N = energy.num_nodes();
  const int L = energy.num_labels();
  const int C = energy.num_cliques();
  const auto& edges = energy.edges();
  const int num_pairwise = static_cast<int>(edges.size());

  // With `movable`: the edges that touch a movable node (the graph holds these only, as its edges 0, 1, ...,
  // and the moves are built over them), and the cost of the others, which no move changes (both ends keep
  // their labels throughout).
  std::vector<int> active_edges;
  double fixed_pairwise = 0;
  if (movable) {
    const uint8_t* const m = movable->data();
    for (int e = 0; e < num_pairwise; ++e) {
      const CrfEnergy::Edge& edge = edges[e];
      if (m[edge.i] || m[edge.j])
        active_edges.push_back(e);
      else
        fixed_pairwise += energy.EdgeCost(edge, labels[edge.i], labels[edge.j]);
    }
  }
  const int* const edge_ids = movable ? active_edges.data() : nullptr;
  const int num_move_edges = movable ? int(active_edges.size()) : num_pairwise;
  // Fixed topology: CRF nodes 0..N-1, then per clique z = N + 2c and y = N + 2c + 1; the move's edges in CRF
  // order (graph edge k = the k-th of them), then per clique and member k the arcs (member -> z) and (y -> member).
  graph.AddNodes(N + 2 * C);
  size_t clique_members = 0;
  for (int c = 0; c < C; ++c) clique_members += energy.clique_nodes(c).size();
  const size_t num_graph_edges = size_t(num_move_edges) + 2 * clique_members;
  if constexpr (requires { graph.ReserveEdges(size_t{0}); }) graph.ReserveEdges(num_graph_edges);
  for (int k = 0; k < num_move_edges; ++k) {
    const CrfEnergy::Edge& e = edges[edge_ids ? edge_ids[k] : k];
    graph.AddEdge(e.i, e.j, 0, 0);
  }
  std::vector<int> clique_first_edge(C);
  for (int c = 0, next_edge = num_move_edges; c < C; ++c) {
    const int z = N + 2 * c, y = z + 1;
    clique_first_edge[c] = next_edge;
    for (int v : energy.clique_nodes(c)) {
      graph.AddEdge(v, z, 0, 0);
      graph.AddEdge(y, v, 0, 0);
      next_edge += 2;
    }
  }
  // The move's pairwise edges are built in kEdgeChunks fixed ranges in parallel when the graph allows
  // concurrent SetEdgeCapacities on distinct edges and the problem is large enough to pay for it; otherwise
  // in one pass over all edges.
  constexpr int kEdgeChunks = 2;
  bool concurrent_edges = false;
  if constexpr (requires { graph.PrepareConcurrentEdgeUpdates(); }) {
    if (num_pairwise >= (1 << 15)) {
      graph.PrepareConcurrentEdgeUpdates();
      concurrent_edges = true;
    }
  }
  std::vector<std::vector<double>> chunk_delta(concurrent_edges ? kEdgeChunks - 1 : 0, std::vector<double>(size_t(N)));
  const NodeIncidence edge_incidence = energy.EdgeIncidence();
  const NodeIncidence clique_incidence = energy.CliqueIncidence();

  std::vector<double> delta(N + 2 * C);
  std::vector<uint8_t> changed(N, 0);
  std::vector<int> changed_nodes;
  std::vector<std::vector<int>> chunk_changed(concurrent_edges ? kEdgeChunks - 1 : 0);
  std::vector<int> clique_stamp(C, -1);
  std::vector<double> scratch(L, 0.0), old_weight(L, 0.0), new_weight(L, 0.0);
  std::vector<RobustPnMove> plans(C);
  std::vector<double> clique_constant(C);  // Per clique, the constant of its move (concurrent moves).
  std::vector<uint8_t> edge_live(num_graph_edges, 0);  // The edge had a non-zero capacity in the last cut.
  // Pruning (options.prune_decided_nodes): per node a bound on how much its pairwise and clique terms
  // can change when it switches, whatever the other nodes do: sum over its edges of w * (max V - min V)
  // of the edge's model, plus per clique max_l theta_l * w_i (Robust P^n changes by at most that when
  // one node of weight w_i changes label). A node whose unary difference exceeds it is decided.
  // Nodes that may not move are decided "keep" in every move, through the same per-node states.
  std::vector<double> decide_bound;
  std::vector<uint8_t> decided;
  if (movable && !options.prune_decided_nodes) {
    decide_bound.assign(N, std::numeric_limits<double>::infinity());
    decided.assign(N, kMoveFree);
  }
  if (options.prune_decided_nodes) {
    decide_bound.assign(N, 0.0);
    decided.assign(N, kMoveFree);
    std::vector<double> model_range(energy.num_models(), 1.0);  // Potts: 1.
    for (int m = 1; m < energy.num_models(); ++m) {
      float lo = energy.ModelCost(m, 0, 0), hi = lo;
      for (int a = 0; a < L; ++a)
        for (int b = 0; b < L; ++b) {
          lo = std::min(lo, energy.ModelCost(m, a, b));
          hi = std::max(hi, energy.ModelCost(m, a, b));
        }
      model_range[m] = static_cast<double>(hi) - lo;
    }
    for (const CrfEnergy::Edge& e : edges) {
      const double r = static_cast<double>(e.weight) * model_range[e.model];
      decide_bound[e.i] += r;
      decide_bound[e.j] += r;
    }
    for (int c = 0; c < C; ++c) {
      double max_slope = 0;
      for (int l = 0; l < L; ++l) max_slope = std::max(max_slope, energy.clique_slope(c, l));
      const auto nodes = energy.clique_nodes(c);
      const auto weights = energy.clique_weights(c);
      for (size_t k = 0; k < nodes.size(); ++k) decide_bound[nodes[k]] += max_slope * weights[k];
    }
    // Keep the test strict under rounding of the sums above.
    for (double& b : decide_bound) b = b * (1 + 1e-12) + 1e-300;
  }
  // ... and the movable nodes (the per-node passes of a move visit these only; the others stay decided "keep",
  // with terminal capacity 0 and whatever their delta entries hold, which no one reads).
  std::vector<int> move_nodes;
  if (movable) {
    for (int i = 0; i < N; ++i)
      if ((*movable)[i])
        move_nodes.push_back(i);
      else
        decided[i] = kMoveKeep;
  }
  const int* const node_ids = movable ? move_nodes.data() : nullptr;
  const int num_move_nodes = movable ? int(move_nodes.size()) : N;

  double current = energy.Evaluate(labels);
  summary->initial_energy = current;
  // U_i(x_i) per node and its sum, kept up to date (contiguous, unlike the label-major unaries).
  std::vector<float> current_unary(N);
  double current_unary_sum = 0;
  for (int i = 0; i < N; ++i) {
    current_unary[i] = energy.unary(i, labels[i]);
    current_unary_sum += current_unary[i];
  }
  int64_t change_counter = 0;
  std::vector<int64_t> unchanged_at(L, -1);  // change_counter when alpha's expansion last changed nothing.
  std::vector<CrfLabel> order(L);
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 rng(options.seed);
  int stamp = 0;

  for (int sweep = 0; sweep < options.max_sweeps; ++sweep) {
    if (options.randomize_label_order) std::shuffle(order.begin(), order.end(), rng);
    int64_t moves_in_sweep = 0;
    for (const CrfLabel alpha : order) {
      if (unchanged_at[alpha] == change_counter) {
        ++summary->num_skipped_expansions;
        continue;
      }
      // ---- Build the move energy: constant + sum_v delta_v t_v + sum_arcs cap (1 - t_tail) t_head.
      graph.ResetFlow();
      double constant = current_unary_sum;
      int64_t truncated = 0;
      int64_t pruned = 0;
      const bool prune = options.prune_decided_nodes || movable != nullptr;
      {
        // Unary part, and (pruning) the nodes whose move their unary decides: switching costs more than
        // all their pairwise and clique terms could pay back (keep in every optimal move), or gains more
        // than they could charge (switch in every optimal move). Strict dominance, exact.
        const float* plane = energy.unary_plane(alpha).data();
        auto unary_range = [&](int begin, int end) {  // Positions in the move's node list.
          int64_t range_pruned = 0;
          for (int p = begin; p < end; ++p) {
            const int i = node_ids ? node_ids[p] : p;
            if (labels[i] == alpha) {
              delta[i] = 0.0;
              if (prune) decided[i] = kMoveAtAlpha;
              continue;
            }
            const double d = static_cast<double>(plane[i]) - current_unary[i];
            delta[i] = d;
            if (prune) {  // Branch-free: random data mispredicts.
              const uint8_t f = static_cast<uint8_t>((d > decide_bound[i]) * kMoveKeep + (d < -decide_bound[i]) * kMoveSwitch);
              decided[i] = f;
              range_pruned += f != kMoveFree;
            }
          }
          return range_pruned;
        };
        // Per node only (and a count): in kEdgeChunks fixed ranges, in parallel with the edges' condition.
        if (concurrent_edges) {
          std::array<int64_t, kEdgeChunks> chunk_pruned{};
          tbb::parallel_for(0, kEdgeChunks, [&](int k) {
            chunk_pruned[size_t(k)] =
                unary_range(int(int64_t(num_move_nodes) * k / kEdgeChunks), int(int64_t(num_move_nodes) * (k + 1) / kEdgeChunks));
          });
          for (int64_t p : chunk_pruned) pruned += p;
        } else {
          pruned = unary_range(0, num_move_nodes);
        }
      }
      std::fill(delta.begin() + N, delta.end(), 0.0);
      {
        // The pairwise edges in kEdgeChunks fixed ranges, run in parallel when the graph allows concurrent
        // SetEdgeCapacities on distinct edges: each range adds its node terms into its own array (range 0
        // into delta itself) and its constant into its own sum; the ranges are then added in range order, so
        // the result does not depend on the threads. Arcs touching a decided node fold into the other end's
        // unary or the constant and leave the graph. An edge whose two arcs were zero after the last cut
        // carried no flow, so they are still zero: writing zero again is skipped (most edges of decided nodes).
        const CrfLabel* const x = labels.data();
        const uint8_t* const dec = prune ? decided.data() : nullptr;
        auto state = [&](int v) { return dec ? dec[v] : kMoveFree; };
        auto set_edge = [&](int e, double cap) {  // Distinct edges may be set concurrently.
          if (cap > 0 || edge_live[e]) {
            graph.SetEdgeCapacities(e, cap, 0);
            edge_live[e] = cap > 0;
          }
        };
        // An arc tail -> head of capacity cap costs cap (1 - t_tail) t_head; its node terms go to d, its
        // constant to *pc. Branch-free (the states are random): keep -> free: cap t_head; keep -> switch: cap;
        // free -> switch: cap (1 - t_tail); free -> free: the arc; anything else: 0.
        auto arc_into = [&](double* d, double* pc, int e, int tail, int head, double cap, uint8_t ft, uint8_t fh) {
          const bool tail_free = ft == kMoveFree, head_free = fh == kMoveFree;
          const bool tail_keep = ft == kMoveKeep, head_switch = fh == kMoveSwitch;
          set_edge(e, tail_free && head_free ? cap : 0.0);
          d[head] += (tail_keep && head_free) ? cap : 0.0;
          d[tail] -= (tail_free && head_switch) ? cap : 0.0;
          *pc += ((tail_keep || tail_free) && head_switch) ? cap : 0.0;
        };
        // Positions [k_begin, k_end) of the move's edge list: every edge, or (with `movable`) edge_ids.
        auto edge_range = [&](int k_begin, int k_end, double* const d, double* constant_out, int64_t* truncated_out) {
          double pairwise_constant = 0;  // Local accumulator (kept in a register across graph calls).
          int64_t range_truncated = 0;
          auto arc = [&](int g, int tail, int head, double cap, uint8_t ft, uint8_t fh) {  // g: graph edge.
            arc_into(d, &pairwise_constant, g, tail, head, cap, ft, fh);
          };
          for (int k = k_begin; k < k_end; ++k) {
            const int e = edge_ids ? edge_ids[k] : k;
            const CrfEnergy::Edge& edge = edges[e];
            const CrfLabel li = x[edge.i], lj = x[edge.j];
            const bool fi = li == alpha, fj = lj == alpha;  // Fixed at alpha.
            if (edge.model == CrfEnergy::kPottsModel) {
              const double w = edge.weight;
              if (fi || fj) {
                // One end at alpha: [other end keeps its label] w = w - w t_other, a unary term; both: 0.
                if (!(fi && fj)) {
                  pairwise_constant += w;
                  d[fi ? edge.j : edge.i] -= w;
                }
                set_edge(k, 0.0);
              } else {
                // A = w [li != lj], B = C = w, D = 0: E = A + (w - A) t_i - w t_j + (2w - A) (1 - t_i) t_j.
                const double A = li != lj ? w : 0.0;
                pairwise_constant += A;
                d[edge.i] += w - A;
                d[edge.j] -= w;
                arc(k, edge.i, edge.j, 2 * w - A, state(edge.i), state(edge.j));
              }
              continue;
            }
            const double D = energy.EdgeCost(edge, alpha, alpha);
            if (fi || fj) {
              if (fi && fj) {
                pairwise_constant += D;
              } else if (fj) {
                const double A = energy.EdgeCost(edge, li, alpha);
                pairwise_constant += A;
                d[edge.i] += D - A;
              } else {
                const double A = energy.EdgeCost(edge, alpha, lj);
                pairwise_constant += A;
                d[edge.j] += D - A;
              }
              set_edge(k, 0.0);
            } else {
              const double A = energy.EdgeCost(edge, li, lj);
              const double B = energy.EdgeCost(edge, li, alpha);
              const double Cc = energy.EdgeCost(edge, alpha, lj);
              double cap = B + Cc - A - D;
              if (cap < 0) {  // Non-submodular: truncate (the move is verified below).
                ++range_truncated;
                cap = 0;
              }
              pairwise_constant += A;
              d[edge.i] += Cc - A;
              d[edge.j] += D - Cc;
              arc(k, edge.i, edge.j, cap, state(edge.i), state(edge.j));
            }
          }
          *constant_out = pairwise_constant;
          *truncated_out = range_truncated;
        };
        double pairwise_constant = fixed_pairwise;
        if (concurrent_edges) {
          std::array<double, kEdgeChunks> chunk_constant{};
          std::array<int64_t, kEdgeChunks> chunk_truncated{};
          tbb::parallel_for(0, kEdgeChunks, [&](int k) {
            const int e_begin = int(int64_t(num_move_edges) * k / kEdgeChunks), e_end = int(int64_t(num_move_edges) * (k + 1) / kEdgeChunks);
            double* d = k == 0 ? delta.data() : chunk_delta[size_t(k - 1)].data();
            if (k > 0 && node_ids) {
              for (int p = 0; p < num_move_nodes; ++p) chunk_delta[size_t(k - 1)][size_t(node_ids[p])] = 0.0;
            } else if (k > 0) {
              std::fill(chunk_delta[size_t(k - 1)].begin(), chunk_delta[size_t(k - 1)].end(), 0.0);
            }
            edge_range(e_begin, e_end, d, &chunk_constant[size_t(k)], &chunk_truncated[size_t(k)]);
          });
          for (int k = 0; k < kEdgeChunks; ++k) {
            pairwise_constant += chunk_constant[size_t(k)];
            truncated += chunk_truncated[size_t(k)];
          }
          // Node by node, the ranges in order (the same sums), in fixed node ranges on both cores.
          tbb::parallel_for(0, kEdgeChunks, [&](int part) {
            const int p_begin = int(int64_t(num_move_nodes) * part / kEdgeChunks);
            const int p_end = int(int64_t(num_move_nodes) * (part + 1) / kEdgeChunks);
            for (int k = 1; k < kEdgeChunks; ++k) {
              const double* src = chunk_delta[size_t(k - 1)].data();
              if (node_ids) {
                for (int p = p_begin; p < p_end; ++p) delta[node_ids[p]] += src[node_ids[p]];
              } else {
                for (int i = p_begin; i < p_end; ++i) delta[i] += src[i];
              }
            }
          });
        } else {
          double range_constant = 0;
          edge_range(0, num_move_edges, delta.data(), &range_constant, &truncated);
          pairwise_constant += range_constant;
        }
        // Clique arcs, after the edges: per member k, member -> z (capacity alpha_slope w_k when x_k != alpha)
        // and y -> member (dominant_slope w_k when x_k is the dominant label), folded as arc_into folds them.
        // z and y are never decided, so these arcs change only the terms of z and y (a kept member adds its
        // arc to z, a switching member takes its arc from y and adds it to the constant), never a member's:
        // each clique writes its own two nodes and its own edges. So cliques run in parallel when the graph
        // allows concurrent edge updates, each summing its constant on its own (added in clique order after);
        // the graph is exactly the serial loop's, only the rounding of the move's constant (which checks the
        // cut below and nothing else) may differ.
        double* const d = delta.data();
        auto clique_arcs = [&](int c, std::vector<double>* clique_scratch) {
          const RobustPnMove plan = PlanRobustPnMove(energy, c, labels, alpha, clique_scratch);
          plans[c] = plan;
          const int z = N + 2 * c, y = z + 1;
          double clique_constant = plan.constant;
          double dz = 0, dy = 0;
          if (plan.alpha_slope > 0) {  // Q [z = 0] = Q - Q z.
            clique_constant += plan.alpha_aux_cost;
            dz -= plan.alpha_aux_cost;
          }
          if (plan.dominant >= 0) dy += plan.dominant_aux_cost;
          const auto nodes = energy.clique_nodes(c);
          const auto weights = energy.clique_weights(c);
          int e = clique_first_edge[c];
          for (size_t k = 0; k < nodes.size(); ++k, e += 2) {
            const int v = nodes[k];
            const CrfLabel xk = x[v];
            const uint8_t fv = state(v);
            const double to_z = xk != alpha ? plan.alpha_slope * weights[k] : 0.0;
            set_edge(e, fv == kMoveFree ? to_z : 0.0);
            dz += fv == kMoveKeep ? to_z : 0.0;
            const double from_y = xk == plan.dominant ? plan.dominant_slope * weights[k] : 0.0;
            set_edge(e + 1, fv == kMoveFree ? from_y : 0.0);
            dy -= fv == kMoveSwitch ? from_y : 0.0;
            clique_constant += fv == kMoveSwitch ? from_y : 0.0;
          }
          d[z] += dz;
          d[y] += dy;
          return clique_constant;
        };
        if (concurrent_edges && C > 1) {
          tbb::parallel_for(tbb::blocked_range<int>(0, C), [&](const tbb::blocked_range<int>& r) {
            std::vector<double> clique_scratch(size_t(L), 0.0);
            for (int c = r.begin(); c != r.end(); ++c) clique_constant[size_t(c)] = clique_arcs(c, &clique_scratch);
          });
          for (int c = 0; c < C; ++c) pairwise_constant += clique_constant[size_t(c)];
        } else {
          for (int c = 0; c < C; ++c) pairwise_constant += clique_arcs(c, &scratch);
        }
        constant += pairwise_constant;
      }
      summary->num_pruned_nodes += pruned;
      {
        // Distinct nodes in kEdgeChunks fixed ranges (concurrently when the graph allows concurrent updates of
        // distinct edges, which covers its nodes' terminal capacities); the constants are summed per range and
        // added in range order (they only check the cut's prediction below).
        // Positions: the move's nodes, then the cliques' auxiliary nodes.
        auto terminal_range = [&](int begin, int end, double* switched, double* negative) {
          for (int p = begin; p < end; ++p) {
            const int v = p < num_move_nodes ? (node_ids ? node_ids[p] : p) : N + (p - num_move_nodes);
            double d = delta[v];
            if (prune && v < N && decided[v] != kMoveFree) {
              if (decided[v] == kMoveSwitch) *switched += d;
              d = 0;
            }
            graph.SetTerminalCapacity(v, d);
            *negative += d < 0 ? d : 0.0;
          }
        };
        const int V = num_move_nodes + 2 * C;
        std::array<double, kEdgeChunks> switched{}, negative{};
        if (concurrent_edges) {
          tbb::parallel_for(0, kEdgeChunks, [&](int k) {
            terminal_range(int(int64_t(V) * k / kEdgeChunks), int(int64_t(V) * (k + 1) / kEdgeChunks), &switched[size_t(k)],
                           &negative[size_t(k)]);
          });
        } else {
          terminal_range(0, V, &switched[0], &negative[0]);
        }
        for (int k = 0; k < kEdgeChunks; ++k) constant += switched[size_t(k)];
        for (int k = 0; k < kEdgeChunks; ++k) constant += negative[size_t(k)];
      }
      // ---- Cut.
      const auto t_flow = Clock::now();
      const double flow = static_cast<double>(graph.Solve());
      summary->max_flow_seconds += std::chrono::duration<double>(Clock::now() - t_flow).count();
      ++summary->num_expansions;
      summary->num_truncated_terms += truncated;

      changed_nodes.clear();
      auto scan_range = [&](int begin, int end, std::vector<int>* out) {  // Positions in the move's node list.
        for (int p = begin; p < end; ++p) {
          const int i = node_ids ? node_ids[p] : p;
          const bool switches = prune ? decided[i] == kMoveSwitch || (decided[i] == kMoveFree && graph.InSinkSegment(i))
                                      : labels[i] != alpha && graph.InSinkSegment(i);
          if (switches) {
            changed[i] = 1;
            out->push_back(i);
          }
        }
      };
      if (concurrent_edges) {  // Fixed node ranges, their lists joined in order: ascending, as one pass.
        tbb::parallel_for(0, kEdgeChunks, [&](int k) {
          std::vector<int>* out = k == 0 ? &changed_nodes : &chunk_changed[size_t(k - 1)];
          out->clear();
          scan_range(int(int64_t(num_move_nodes) * k / kEdgeChunks), int(int64_t(num_move_nodes) * (k + 1) / kEdgeChunks), out);
        });
        for (const std::vector<int>& more : chunk_changed) changed_nodes.insert(changed_nodes.end(), more.begin(), more.end());
      } else {
        scan_range(0, num_move_nodes, &changed_nodes);
      }
      const double change = ExpansionEnergyChange(energy, edge_incidence, clique_incidence, labels, current_unary, changed_nodes,
                                                  changed, alpha, &clique_stamp, stamp++, &old_weight, &new_weight);
      const double tolerance = options.consistency_tolerance * (1.0 + std::abs(current));
      if (truncated == 0) {
        // The cut value is the move energy of the chosen move; the move "keep everything" costs `current`.
        const double predicted = constant + flow;
        if (std::abs(predicted - (current + change)) > tolerance || change > tolerance) {
          std::ostringstream os;
          os << "expansion of label " << alpha << ": energy " << current << " -> " << current + change
             << " but the cut predicts " << predicted << " (" << changed_nodes.size() << " nodes changed)";
          ExpansionInvariantFailed(os.str());
        }
      }
      const bool improves = change < -1e-12 * (1.0 + std::abs(current));
      if (improves) {
        const float* plane = energy.unary_plane(alpha).data();
        for (int i : changed_nodes) {
          labels[i] = alpha;
          current_unary_sum += static_cast<double>(plane[i]) - current_unary[i];
          current_unary[i] = plane[i];
        }
        current += change;
        ++change_counter;
        ++moves_in_sweep;
        ++summary->num_moves;
      } else {
        if (!changed_nodes.empty() && change > 0) ++summary->num_rejected_moves;
        unchanged_at[alpha] = change_counter;
      }
      for (int i : changed_nodes) changed[i] = 0;
      summary->energy_per_expansion.push_back(current);
      summary->expansion_labels.push_back(alpha);
      if (options.log_expansions) {
        SEMVOX_LOG(kDebug, "alpha-expansion sweep " << sweep + 1 << " label " << alpha << ": E = " << current
                                                    << (improves ? "" : " (no change)") << ", "
                                                    << (improves ? changed_nodes.size() : 0) << " nodes changed");
      }
    }
    // Exact re-evaluation at the end of each sweep (no drift from the incremental sums).
    const double exact = energy.Evaluate(labels);
    if (exact > summary->initial_energy + options.consistency_tolerance * (1.0 + std::abs(summary->initial_energy)) ||
        (!summary->energy_per_sweep.empty() &&
         exact > summary->energy_per_sweep.back() + options.consistency_tolerance * (1.0 + std::abs(exact)))) {
      ExpansionInvariantFailed("energy rose over a sweep");
    }
    const double before_sweep = summary->energy_per_sweep.empty() ? summary->initial_energy : summary->energy_per_sweep.back();
    current = exact;
    current_unary_sum = 0;
    for (int i = 0; i < N; ++i) current_unary_sum += current_unary[i];
    summary->energy_per_sweep.push_back(exact);
    summary->num_sweeps = sweep + 1;
    SEMVOX_LOG(kDebug, "alpha-expansion sweep " << sweep + 1 << ": E = " << exact << ", " << moves_in_sweep
                                                << " moves");
    if (moves_in_sweep == 0) {
      summary->converged = true;
      break;
    }
    if (options.min_sweep_improvement > 0 && before_sweep - exact < options.min_sweep_improvement * std::abs(before_sweep)) {
      SEMVOX_LOG(kDebug, "alpha-expansion: sweep " << sweep + 1 << " lowered E by " << before_sweep - exact << " (< "
                                                   << options.min_sweep_improvement << " |E|), stopping");
      break;
    }
  }
  summary->final_energy = current;
  summary->graph_bytes = graph.MemoryBytes();
  summary->seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  return Status::Ok();
}

}  // namespace semvox::crf_internal
