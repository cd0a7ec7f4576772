// CrfEnergy: a multi-label energy over N nodes and L labels, the problem the semvox CRF solvers minimise.
//
//   E(x) = sum_i U_i(x_i)                                   unary, one cost per node and label
//        + sum_(i,j) w_ij V_m(ij)(x_i, x_j)                 pairwise, per-edge weight x label model
//        + sum_c psi_c(x_c)                                  Robust P^n higher-order cliques
//
// Pairwise models: model 0 (kPottsModel) is Potts, V(a, b) = [a != b], so per-edge weights give the
// generalised Potts model; further models are dense L x L label-compatibility matrices V(a, b) with
// a = label of the edge's first node.
//
// Robust P^n (Kohli, Ladicky & Torr, "Robust Higher Order Potentials for Enforcing Label Consistency",
// IJCV 82(3), 2009, Eq. 9-10): for a clique c with node weights w_i (default 1), total weight W,
// truncation Q, per-label costs gamma_l <= gamma_max,
//
//   psi_c(x_c) = min( gamma_max,  min_l gamma_l + (gamma_max - gamma_l) / Q * N_l(x_c) ),
//   N_l(x_c)  = sum of w_i over the clique's nodes with x_i != l   (the weight "disagreeing" with l).
//
// (Q -> 0 gives the P^n Potts model.) semvox requires 0 < Q <= W / 2: then at most one label can be
// below gamma_max and the alpha-expansion move is exactly graph-representable with two auxiliary nodes
// per clique (Kohli et al. 2009, Sec. 5; see robust_pn.h).
//
// The Voxel-CRF (Kim et al., ICCV 2013, Eq. 1) is this energy with voxels as nodes, 3D/2D adjacencies as
// edges (weights from spatial relation and colour cluster, Eq. 5-8) and planes / detections as cliques.
//
// Building the energy is programming, not user input: out-of-range indices abort with a message.
// Check() validates the values (finite costs, Q, gamma) and names the offending field.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace semvox {

using CrfLabel = int32_t;

// Robust P^n clique parameters (see above).
struct RobustPnParams {
  float gamma_max = 1.0f;    // Cost of an inconsistent clique. >= every gamma.
  float truncation_q = 1.0f; // Weight of disagreeing nodes at which the cost saturates. 0 < Q <= W / 2.
  std::vector<float> gamma;  // Per-label cost of a fully consistent clique; empty = all 0.
};

// Node -> incident items (edges or cliques), compressed rows.
struct NodeIncidence {
  std::vector<int> offsets;  // num_nodes + 1.
  std::vector<int> items;
  std::span<const int> Of(int node) const {
    return {items.data() + offsets[node], static_cast<size_t>(offsets[node + 1] - offsets[node])};
  }
};

class CrfEnergy {
 public:
  static constexpr int kPottsModel = 0;

  struct Edge {
    int i = 0, j = 0;    // Nodes; i != j.
    float weight = 0;    // w_ij.
    int model = kPottsModel;
  };

  CrfEnergy(int num_nodes, int num_labels);

  int num_nodes() const { return num_nodes_; }
  int num_labels() const { return num_labels_; }

  // ---- Unary: U_i(l), 0 by default. Stored label-major (label * N + node): an expansion of label alpha
  // reads the contiguous plane U_.(alpha) instead of one cache line per node.
  void SetUnary(int node, CrfLabel label, float cost) { unary_[Index(node, label)] = cost; }
  void SetUnaries(int node, std::span<const float> costs);  // costs.size() == L.
  float unary(int node, CrfLabel label) const { return unary_[static_cast<size_t>(label) * num_nodes_ + node]; }
  // All unaries, label-major: element label * N + node.
  std::span<float> mutable_unaries() { return unary_; }
  std::span<const float> unaries() const { return unary_; }
  // U_i(label) for i = 0..N-1.
  std::span<const float> unary_plane(CrfLabel label) const {
    return {unary_.data() + static_cast<size_t>(label) * num_nodes_, static_cast<size_t>(num_nodes_)};
  }

  // ---- Pairwise.
  // Adds a dense L x L label-compatibility model (row-major, V(a, b) = matrix[a * L + b]); returns its id.
  int AddCompatibilityModel(std::vector<float> matrix);
  int num_models() const { return static_cast<int>(models_.size()) + 1; }
  // V_model(a, b) without the edge weight.
  float ModelCost(int model, CrfLabel a, CrfLabel b) const {
    return model == kPottsModel ? (a != b ? 1.0f : 0.0f)
                                : models_[model - 1][static_cast<size_t>(a) * num_labels_ + b];
  }
  // True when V_model is a metric (V(a,b) = 0 iff a = b, symmetric, triangle inequality): then every
  // alpha-expansion move is exactly representable and the result is within 2 max V / min V of optimal.
  bool IsMetric(int model) const;
  void AddEdge(int i, int j, float weight, int model = kPottsModel);
  void ReserveEdges(size_t count) { edges_.reserve(count); }
  const std::vector<Edge>& edges() const { return edges_; }
  float EdgeCost(const Edge& e, CrfLabel a, CrfLabel b) const {
    return e.model == kPottsModel ? (a != b ? e.weight : 0.0f) : e.weight * ModelCost(e.model, a, b);
  }

  // ---- Robust P^n cliques. `node_weights` empty = all 1. Returns the clique id.
  int AddRobustPnClique(std::vector<int> nodes, const RobustPnParams& params,
                        std::vector<float> node_weights = {});
  int num_cliques() const { return static_cast<int>(clique_offsets_.size()) - 1; }
  std::span<const int> clique_nodes(int c) const {
    return {clique_nodes_.data() + clique_offsets_[c], static_cast<size_t>(clique_offsets_[c + 1] - clique_offsets_[c])};
  }
  std::span<const float> clique_weights(int c) const {
    return {clique_weights_.data() + clique_offsets_[c], static_cast<size_t>(clique_offsets_[c + 1] - clique_offsets_[c])};
  }
  double clique_total_weight(int c) const { return clique_total_weight_[c]; }
  float clique_gamma(int c, CrfLabel l) const { return clique_gamma_[static_cast<size_t>(c) * num_labels_ + l]; }
  float clique_gamma_max(int c) const { return clique_gamma_max_[c]; }
  float clique_truncation(int c) const { return clique_q_[c]; }
  // theta_l = (gamma_max - gamma_l) / Q, the cost per unit of disagreeing weight.
  double clique_slope(int c, CrfLabel l) const {
    return (static_cast<double>(clique_gamma_max_[c]) - clique_gamma(c, l)) / clique_q_[c];
  }
  // psi_c from the clique's weight per label (label_weight.size() == L).
  double CliquePotentialFromWeights(int c, std::span<const double> label_weight) const;
  // psi_c for a full labelling (reads the clique's nodes).
  double CliquePotential(int c, std::span<const CrfLabel> labels) const;

  // ---- Whole energy.
  // Validates values; false with a message naming the field, value and violated constraint.
  bool Check(std::string* error) const;
  // E(x) and its parts; labels.size() == N, every label in [0, L).
  double Evaluate(std::span<const CrfLabel> labels) const;
  double UnaryEnergy(std::span<const CrfLabel> labels) const;
  double PairwiseEnergy(std::span<const CrfLabel> labels) const;
  double HigherOrderEnergy(std::span<const CrfLabel> labels) const;
  // Per node the label of least unary cost (lowest label on ties).
  std::vector<CrfLabel> UnaryArgmin() const;

  NodeIncidence EdgeIncidence() const;
  NodeIncidence CliqueIncidence() const;
  size_t MemoryBytes() const;

 private:
  size_t Index(int node, CrfLabel label) const;

  int num_nodes_ = 0;
  int num_labels_ = 0;
  std::vector<float> unary_;
  std::vector<std::vector<float>> models_;  // Model m >= 1 at models_[m - 1].
  std::vector<Edge> edges_;
  std::vector<int> clique_offsets_{0};
  std::vector<int> clique_nodes_;
  std::vector<float> clique_weights_;
  std::vector<double> clique_total_weight_;
  std::vector<float> clique_gamma_;  // C x L.
  std::vector<float> clique_gamma_max_;
  std::vector<float> clique_q_;
};

}  // namespace semvox
