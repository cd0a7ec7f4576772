// Inference on pairwise CRFs in the log domain:
// - exact sum-product marginals and max-product MAP on trees and forests, O(n m^2) for n nodes and m
//   labels (MST-CRF paper Sec. 3.2: "belief propagation ... exactly infer the marginal distribution of each
//   node, and the max-product algorithm to find the MAP assignment");
// - loopy sum-product belief propagation on any graph (heterogeneous-coverage paper Sec. III-A/C), with
//   synchronous (flooding) updates, optional damping, and MAP decoded as the argmax of each belief.
//
//   p(x) = 1/Z prod_i phi_i(x_i) prod_(i,j) psi_ij(x_i, x_j)          (Eq. 1 of both papers)
//   PairwiseModel holds log phi (n x m) and, per edge, log psi (m x m).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

struct PairwiseModel {
  struct Edge {
    int i = 0, j = 0;                 // Node indices, i != j.
    std::vector<double> log_pairwise; // m x m, row-major: [label_i * m + label_j].
  };
  int num_labels = 0;
  std::vector<double> log_unary;  // n x m, row-major: [node * m + label].
  std::vector<Edge> edges;

  int num_nodes() const { return num_labels > 0 ? int(log_unary.size()) / num_labels : 0; }
  // Sizes, index ranges, finiteness of every log potential.
  bool Check(std::string* error) const;
  // sum_i log phi_i(x_i) + sum_(i,j) log psi_ij(x_i, x_j): log p(x) + log Z.
  double LogScore(std::span<const int> labels) const;
};

struct Marginals {
  int num_labels = 0;
  std::vector<double> p;      // n x m, each row sums to one.
  double log_partition = 0;   // log Z (exact inference only; NaN from loopy BP).
  double at(int node, int label) const { return p[size_t(node) * size_t(num_labels) + size_t(label)]; }
};

// Exact marginals by two-pass sum-product. Fails (kInvalidInput) when the graph has a cycle or a
// duplicate edge.
Status TreeSumProduct(const PairwiseModel& model, Marginals* marginals);
// Exact MAP assignment by max-product with back-tracking; ties go to the lower label. Same failures.
Status TreeMaxProduct(const PairwiseModel& model, std::vector<int>* labels);

struct LoopyBpOptions {
  // Upper bound on synchronous sweeps over all messages. >= 1.
  int max_iterations = 200;
  // Each new log message is (1 - damping) new + damping old. [0, 1).
  double damping = 0.0;
  // Converged when no normalised log message changes by more than this. > 0.
  double tolerance = 1e-10;

  bool Check(std::string* error) const;
};

struct LoopyBpSummary {
  int iterations = 0;
  bool converged = false;
  double max_message_change = 0;  // In the last sweep.
};

// Loopy sum-product BP. On a tree it converges to the exact marginals within diameter + 1 sweeps.
Status LoopyBeliefPropagation(const PairwiseModel& model, const LoopyBpOptions& options, Marginals* marginals,
                              LoopyBpSummary* summary = nullptr);

// Argmax of every row of `marginals` (ties to the lower label).
std::vector<int> DecodeMaxMarginals(const Marginals& marginals);

}  // namespace semvox
