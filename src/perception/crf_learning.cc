#include "perception/crf_learning.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

namespace semvox {

CrfTrainingGraph MakeCrfTrainingGraph(const ViewObservations& observations, const ViewGraph& graph,
                                      const std::vector<std::vector<double>>& probabilities,
                                      const std::vector<std::vector<double>>& image_only_probabilities,
                                      bool use_distance_term, const ViewCrfOptions& options, std::vector<int> labels) {
  CrfTrainingGraph out;
  const size_t n = observations.superpixels.size();
  out.num_labels = n > 0 ? int(probabilities[0].size()) : 0;
  out.log_probability.resize(n * size_t(out.num_labels));
  for (size_t s = 0; s < n; ++s) {
    const bool image_only = !image_only_probabilities.empty() && !observations.superpixels[s].has_depth;
    const std::vector<double>& p = image_only ? image_only_probabilities[s] : probabilities[s];
    for (int l = 0; l < out.num_labels; ++l) out.log_probability[s * size_t(out.num_labels) + size_t(l)] = std::log(p[size_t(l)]);
  }
  for (const ViewGraph::Edge& e : graph.edges) {
    const auto& a = observations.superpixels[size_t(e.i)];
    const auto& b = observations.superpixels[size_t(e.j)];
    CrfTrainingGraph::Edge te;
    te.i = e.i;
    te.j = e.j;
    te.colour_distance = double((a.lab_mean - b.lab_mean).norm()) / options.colour_scale_lab;
    if (use_distance_term && e.kind == ViewEdgeKind::kDepth)
      te.spatial_distance = (a.centroid_world - b.centroid_world).norm() / options.distance_scale_m;
    out.edges.push_back(te);
  }
  out.labels = std::move(labels);
  return out;
}

bool CrfLearningOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (max_iterations < 1) return fail("max_iterations = " + std::to_string(max_iterations) + ". Violated constraint: max_iterations >= 1");
  if (!(l2 >= 0)) return fail("l2 = " + std::to_string(l2) + ". Violated constraint: l2 >= 0");
  return true;
}

double NegativeLogPseudoLikelihood(const std::vector<CrfTrainingGraph>& graphs, const double w[3], double gradient[3]) {
  double total = 0;
  double g[3] = {0, 0, 0};
  int nodes = 0;
  std::vector<double> phi_c, phi_d, a;
  for (const CrfTrainingGraph& graph : graphs) {
    const int m = graph.num_labels;
    const size_t n = graph.labels.size();
    // Per node and label: phi_c(l) = -sum_j g1(l, x_j), phi_d(l) = -sum_j g2(l, x_j).
    phi_c.assign(n * size_t(m), 0.0);
    phi_d.assign(n * size_t(m), 0.0);
    for (const CrfTrainingGraph::Edge& e : graph.edges) {
      const int xi = graph.labels[size_t(e.i)], xj = graph.labels[size_t(e.j)];
      if (xi < 0 || xj < 0) continue;
      const double same_c = SameLabelFeature(e.colour_distance), diff_c = DifferentLabelFeature(e.colour_distance);
      const bool has_d = e.spatial_distance >= 0;
      const double same_d = has_d ? SameLabelFeature(e.spatial_distance) : 0, diff_d = has_d ? DifferentLabelFeature(e.spatial_distance) : 0;
      for (int l = 0; l < m; ++l) {
        phi_c[size_t(e.i) * m + l] -= l == xj ? same_c : diff_c;
        phi_c[size_t(e.j) * m + l] -= l == xi ? same_c : diff_c;
        phi_d[size_t(e.i) * m + l] -= l == xj ? same_d : diff_d;
        phi_d[size_t(e.j) * m + l] -= l == xi ? same_d : diff_d;
      }
    }
    a.resize(size_t(m));
    for (size_t s = 0; s < n; ++s) {
      const int x = graph.labels[s];
      if (x < 0) continue;
      ++nodes;
      const double* lp = &graph.log_probability[s * size_t(m)];
      double mx = -1e300;
      for (int l = 0; l < m; ++l) {
        a[size_t(l)] = w[0] * lp[l] + w[1] * phi_c[s * m + l] + w[2] * phi_d[s * m + l];
        mx = std::max(mx, a[size_t(l)]);
      }
      double z = 0;
      for (int l = 0; l < m; ++l) z += std::exp(a[size_t(l)] - mx);
      const double log_z = mx + std::log(z);
      total += log_z - a[size_t(x)];
      for (int l = 0; l < m; ++l) {
        const double p = std::exp(a[size_t(l)] - log_z);
        g[0] += p * lp[l];
        g[1] += p * phi_c[s * m + l];
        g[2] += p * phi_d[s * m + l];
      }
      g[0] -= lp[x];
      g[1] -= phi_c[s * m + x];
      g[2] -= phi_d[s * m + x];
    }
  }
  const double scale = nodes > 0 ? 1.0 / nodes : 0.0;
  if (gradient)
    for (int k = 0; k < 3; ++k) gradient[k] = g[k] * scale;
  return total * scale;
}

namespace {

// Cost in t = log w; the distance weight stays fixed when it is not learned.
class PseudoLikelihoodCost : public ceres::FirstOrderFunction {
 public:
  PseudoLikelihoodCost(const std::vector<CrfTrainingGraph>* graphs, double l2, bool learn_distance, double fixed_distance)
      : graphs_(graphs), l2_(l2), learn_distance_(learn_distance), fixed_distance_(fixed_distance) {}
  bool Evaluate(const double* t, double* cost, double* gradient) const override {
    const double w[3] = {std::exp(t[0]), std::exp(t[1]), learn_distance_ ? std::exp(t[2]) : fixed_distance_};
    double gw[3];
    *cost = NegativeLogPseudoLikelihood(*graphs_, w, gw);
    for (int k = 0; k < NumParameters(); ++k) {
      *cost += 0.5 * l2_ * t[k] * t[k];
      if (gradient) gradient[k] = gw[k] * w[k] + l2_ * t[k];
    }
    return std::isfinite(*cost);
  }
  int NumParameters() const override { return learn_distance_ ? 3 : 2; }

 private:
  const std::vector<CrfTrainingGraph>* graphs_;
  double l2_;
  bool learn_distance_;
  double fixed_distance_;
};

}  // namespace

Result<ViewCrfOptions> LearnCrfWeights(const std::vector<CrfTrainingGraph>& graphs, const ViewCrfOptions& initial,
                                       const CrfLearningOptions& options, CrfLearningSummary* summary) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("CRF learning: " + error);
  if (!initial.Check(&error)) return Status::InvalidInput("CRF learning: " + error);
  int nodes = 0;
  for (const CrfTrainingGraph& g : graphs) {
    if (g.log_probability.size() != g.labels.size() * size_t(g.num_labels))
      return Status::InvalidInput("CRF learning: a training graph's probabilities do not match its labels");
    for (int x : g.labels) nodes += x >= 0;
  }
  if (nodes == 0) return Status::InvalidInput("CRF learning: no labelled node");
  const bool learn_d = options.learn_distance_weight;
  // Ceres needs strictly positive starting weights in log space.
  auto start = [](double w) { return std::log(std::max(w, 1e-3)); };
  double t[3] = {start(initial.unary_weight), start(initial.colour_weight), start(initial.distance_weight)};
  const double w0[3] = {std::exp(t[0]), std::exp(t[1]), learn_d ? std::exp(t[2]) : initial.distance_weight};
  CrfLearningSummary local;
  local.nodes = nodes;
  local.initial_nlpl = NegativeLogPseudoLikelihood(graphs, w0, nullptr);
  ceres::GradientProblem problem(new PseudoLikelihoodCost(&graphs, options.l2, learn_d, initial.distance_weight));
  ceres::GradientProblemSolver::Options solver_options;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.logging_type = ceres::SILENT;
  ceres::GradientProblemSolver::Summary ceres_summary;
  ceres::Solve(solver_options, problem, t, &ceres_summary);
  ViewCrfOptions out = initial;
  out.unary_weight = std::exp(t[0]);
  out.colour_weight = std::exp(t[1]);
  if (learn_d) out.distance_weight = std::exp(t[2]);
  const double w1[3] = {out.unary_weight, out.colour_weight, out.distance_weight};
  local.final_nlpl = NegativeLogPseudoLikelihood(graphs, w1, nullptr);
  local.iterations = int(ceres_summary.iterations.size());
  local.ceres_report = ceres_summary.BriefReport();
  if (summary) *summary = local;
  return out;
}

}  // namespace semvox
