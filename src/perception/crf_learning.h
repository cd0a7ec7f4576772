// CRF weights learned by minimising the negative log pseudo-likelihood (heterogeneous-coverage paper
// Sec. III-A: "the learning of the weights ... by minimizing the negative log pseudo-likelihood"), with
// Ceres' gradient-problem solver (L-BFGS) and analytic gradients.
//
//   NLPL(w) = sum_s [ log sum_l exp a_s(l) - a_s(x_s) ] + (l2 / 2) |log w|^2
//   a_s(l)  = w_u log P_s(l) - sum_(j in N(s)) [ w_c g1(l, x_j) + w_d g2(l, x_j) ]
//
// with x the ground-truth labels (view_crf.h gives g1, g2). The weights are parametrised as w = exp(t) so
// they stay positive, as ViewCrfOptions requires; the l2 term pulls t towards 0 (w towards 1).
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "perception/observations.h"
#include "perception/view_crf.h"

namespace semvox {

// The features of one view's CRF with its ground truth, for learning.
struct CrfTrainingGraph {
  int num_labels = 0;
  std::vector<double> log_probability;  // n x m: log P_s(l), the unary feature (-f).
  struct Edge {
    int i = 0, j = 0;
    double colour_distance = 0;  // LAB distance / colour_scale_lab.
    double spatial_distance = -1;  // 3D distance / distance_scale_m; < 0 when the edge has no g2 term.
  };
  std::vector<Edge> edges;
  std::vector<int> labels;  // Ground truth per node, -1 = unknown (not a centre; its edges are dropped).
};

// The features of the CRF BuildViewCrf would build from the same arguments (scales from `options`).
CrfTrainingGraph MakeCrfTrainingGraph(const ViewObservations& observations, const ViewGraph& graph,
                                      const std::vector<std::vector<double>>& probabilities,
                                      const std::vector<std::vector<double>>& image_only_probabilities,
                                      bool use_distance_term, const ViewCrfOptions& options, std::vector<int> labels);

struct CrfLearningOptions {
  // L-BFGS iterations. >= 1.
  int max_iterations = 100;
  // Weight of (l2 / 2) |log w|^2 per training node (scaled by the node count). >= 0.
  double l2 = 1e-3;
  // Learn w_d (the union CRF's g2); when false it stays at the initial value.
  bool learn_distance_weight = true;

  bool Check(std::string* error) const;
};

struct CrfLearningSummary {
  double initial_nlpl = 0;  // Per node, at the initial weights.
  double final_nlpl = 0;    // Per node, at the learned weights.
  int iterations = 0;
  int nodes = 0;
  std::string ceres_report;
};

// Returns `initial` with unary_weight, colour_weight (and distance_weight) replaced by the learned values.
Result<ViewCrfOptions> LearnCrfWeights(const std::vector<CrfTrainingGraph>& graphs, const ViewCrfOptions& initial,
                                       const CrfLearningOptions& options, CrfLearningSummary* summary = nullptr);

// NLPL per node and its gradient with respect to (w_u, w_c, w_d), no regulariser (for tests).
double NegativeLogPseudoLikelihood(const std::vector<CrfTrainingGraph>& graphs, const double weights[3],
                                   double gradient[3]);

}  // namespace semvox
