#include "perception/view_crf.h"

#include "perception/spanning_tree.h"

namespace semvox {

bool ViewCrfOptions::Check(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(unary_weight >= 0)) return fail("unary_weight = " + std::to_string(unary_weight) + ". Violated constraint: unary_weight >= 0");
  if (!(colour_weight >= 0)) return fail("colour_weight = " + std::to_string(colour_weight) + ". Violated constraint: colour_weight >= 0");
  if (!(distance_weight >= 0))
    return fail("distance_weight = " + std::to_string(distance_weight) + ". Violated constraint: distance_weight >= 0");
  if (!(colour_scale_lab > 0))
    return fail("colour_scale_lab = " + std::to_string(colour_scale_lab) + ". Violated constraint: colour_scale_lab > 0");
  if (!(distance_scale_m > 0))
    return fail("distance_scale_m = " + std::to_string(distance_scale_m) + ". Violated constraint: distance_scale_m > 0");
  return true;
}

ViewGraph BuildTreeGraph(const ViewObservations& observations) {
  ViewGraph graph;
  graph.num_nodes = int(observations.superpixels.size());
  std::vector<int> with_depth;
  std::vector<Eigen::Vector3d> centroids;
  for (int s = 0; s < graph.num_nodes; ++s)
    if (observations.superpixels[size_t(s)].has_depth) {
      with_depth.push_back(s);
      centroids.push_back(observations.superpixels[size_t(s)].centroid_world);
    }
  for (const WeightedEdge& e : EuclideanMinimumSpanningTree(centroids))
    graph.edges.push_back({with_depth[size_t(e.i)], with_depth[size_t(e.j)], ViewEdgeKind::kDepth});
  return graph;
}

ViewGraph BuildUnionCoverageGraph(const ViewObservations& observations) {
  ViewGraph graph = BuildTreeGraph(observations);
  std::vector<WeightedEdge> candidates;
  for (const auto& [i, j] : observations.image_adjacency) {
    const auto& a = observations.superpixels[size_t(i)];
    const auto& b = observations.superpixels[size_t(j)];
    if (a.has_depth && b.has_depth) continue;
    candidates.push_back({i, j, double((a.lab_mean - b.lab_mean).norm())});
  }
  for (const WeightedEdge& e : MinimumSpanningForest(graph.num_nodes, std::move(candidates)))
    graph.edges.push_back({e.i, e.j, ViewEdgeKind::kImage});
  return graph;
}

Result<PairwiseModel> BuildViewCrf(const ViewObservations& observations, const ViewGraph& graph,
                                   const std::vector<std::vector<double>>& probabilities,
                                   const std::vector<std::vector<double>>& image_only_probabilities,
                                   bool use_distance_term, const ViewCrfOptions& options) {
  std::string error;
  if (!options.Check(&error)) return Status::InvalidInput("view CRF: " + error);
  const size_t n = observations.superpixels.size();
  if (probabilities.size() != n || graph.num_nodes != int(n) ||
      (!image_only_probabilities.empty() && image_only_probabilities.size() != n) || n == 0)
    return Status::InvalidInput("view CRF: expected " + std::to_string(n) + " superpixels in the graph (" +
                                std::to_string(graph.num_nodes) + ") and probability rows (" +
                                std::to_string(probabilities.size()) + ")");
  const int m = int(probabilities[0].size());
  if (m < 1) return Status::InvalidInput("view CRF: no classes");
  PairwiseModel model;
  model.num_labels = m;
  model.log_unary.resize(n * size_t(m));
  for (size_t s = 0; s < n; ++s) {
    const bool image_only = !image_only_probabilities.empty() && !observations.superpixels[s].has_depth;
    const std::vector<double>& p = image_only ? image_only_probabilities[s] : probabilities[s];
    if (int(p.size()) != m) return Status::InvalidInput("view CRF: superpixel " + std::to_string(s) + " has " +
                                                        std::to_string(p.size()) + " probabilities, expected " + std::to_string(m));
    for (int l = 0; l < m; ++l) {
      if (!(p[size_t(l)] > 0))
        return Status::InvalidInput("view CRF: probability of class " + std::to_string(l) + " at superpixel " +
                                    std::to_string(s) + " is not positive (hint: KnnOptions::probability_floor > 0)");
      model.log_unary[s * size_t(m) + size_t(l)] = options.unary_weight * std::log(p[size_t(l)]);  // -w_u f, Eq. 3.
    }
  }
  for (const ViewGraph::Edge& e : graph.edges) {
    const auto& a = observations.superpixels[size_t(e.i)];
    const auto& b = observations.superpixels[size_t(e.j)];
    const double dc = double((a.lab_mean - b.lab_mean).norm()) / options.colour_scale_lab;
    double same = options.colour_weight * SameLabelFeature(dc), diff = options.colour_weight * DifferentLabelFeature(dc);
    if (use_distance_term && e.kind == ViewEdgeKind::kDepth) {
      const double dd = (a.centroid_world - b.centroid_world).norm() / options.distance_scale_m;
      same += options.distance_weight * SameLabelFeature(dd);
      diff += options.distance_weight * DifferentLabelFeature(dd);
    }
    PairwiseModel::Edge edge{e.i, e.j, std::vector<double>(size_t(m) * size_t(m), -diff)};
    for (int l = 0; l < m; ++l) edge.log_pairwise[size_t(l) * size_t(m) + size_t(l)] = -same;
    model.edges.push_back(std::move(edge));
  }
  return model;
}

ImageF32 PixelProbabilities(const Superpixels& superpixels, const Marginals& marginals) {
  const int m = marginals.num_labels;
  ImageF32 out(superpixels.label.width, superpixels.label.height, m);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const int s = superpixels.label.at(x, y);
      for (int l = 0; l < m; ++l) out.at(x, y, l) = float(marginals.at(s, l));
    }
  return out;
}

Image<int32_t> PixelLabels(const Superpixels& superpixels, const std::vector<int>& superpixel_labels) {
  Image<int32_t> out(superpixels.label.width, superpixels.label.height, 1, -1);
  for (size_t k = 0; k < out.data.size(); ++k) out.data[k] = superpixel_labels[size_t(superpixels.label.data[k])];
  return out;
}

}  // namespace semvox
