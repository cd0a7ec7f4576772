// View CRFs over superpixels: the graph, the potentials and the per-pixel output.
//
// Tree CRF (MST-CRF paper Sec. 3.2-3.3): nodes are the superpixels, edges the minimum spanning tree over
// the 3D centroids of those with depth; unary f = -log P_s (Eq. 3, from the k-NN of Eq. 4), pairwise g of
// Eq. 6 on LAB colour distance. Superpixels without depth stay unconnected (unary only): exact BP handles
// the forest.
//
// Union-coverage CRF (heterogeneous-coverage paper Sec. III-C): the same 3D tree, plus the superpixels
// without depth joined through a minimum spanning forest over LAB colour distance of those image-adjacency
// edges that touch at least one superpixel without depth. Unary f1 (image-only k-NN, Eq. 3) without depth,
// f2 (image + 3D k-NN, Eq. 6 there) with depth; pairwise g1 on colour (Eq. 5) on every edge and g2 on 3D
// distance (Eq. 7) on the 3D edges. The graph has loops: loopy BP.
//
// Potentials are written as costs with non-negative weights:
//   log phi_s(l)    = -w_u f(l) = w_u log P_s(l)
//   log psi_ij(l,l') = -w_c g1(l,l') - w_d g2(l,l'),  g(l,l') = 1 - exp(-d/s) if l = l', exp(-d/s) otherwise
// where d is the LAB distance (scale s = colour_scale_lab) or 3D distance (s = distance_scale_m). The
// papers' Eq. 2 has the same form with learned signed weights and s = 1; the scales are ours, so that the
// term does not saturate at LAB distances of a few units.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "core/image.h"
#include "perception/belief_propagation.h"
#include "perception/observations.h"
#include "perception/superpixels.h"

namespace semvox {

struct ViewCrfOptions {
  // w_u: weight of the unary -log P_s. >= 0.
  double unary_weight = 1.0;
  // w_c: weight of the colour pairwise g1 (Eq. 6 / Eq. 5). >= 0.
  double colour_weight = 1.0;
  // w_d: weight of the 3D-distance pairwise g2 (Eq. 7) on the union graph's 3D edges. >= 0.
  double distance_weight = 1.0;
  // LAB distance scale inside exp(-d / s), LAB units. > 0.
  double colour_scale_lab = 10.0;
  // 3D distance scale inside exp(-d / s), metres. > 0.
  double distance_scale_m = 0.5;

  bool Check(std::string* error) const;
};

enum class ViewEdgeKind { kDepth, kImage };  // 3D-MST edge, or colour-MST edge through a superpixel without depth.

struct ViewGraph {
  struct Edge {
    int i = 0, j = 0;
    ViewEdgeKind kind = ViewEdgeKind::kDepth;
  };
  int num_nodes = 0;
  std::vector<Edge> edges;
};

// MST over the 3D centroids of the superpixels with depth (the others are isolated nodes).
ViewGraph BuildTreeGraph(const ViewObservations& observations);
// The tree graph plus the colour MST over image-adjacency edges touching a superpixel without depth.
ViewGraph BuildUnionCoverageGraph(const ViewObservations& observations);

// g of Eq. 6 / Eq. 5 / Eq. 7 for a distance d already divided by its scale.
inline double SameLabelFeature(double scaled_distance);       // 1 - exp(-d)
inline double DifferentLabelFeature(double scaled_distance);  // exp(-d)

// The CRF of `graph`: unary from `probabilities` (per superpixel, num_labels values, all > 0), or for
// superpixels without depth from `image_only_probabilities` when that is non-empty (the union CRF's f1).
// Colour pairwise on every edge; distance pairwise on kDepth edges when `use_distance_term`.
Result<PairwiseModel> BuildViewCrf(const ViewObservations& observations, const ViewGraph& graph,
                                   const std::vector<std::vector<double>>& probabilities,
                                   const std::vector<std::vector<double>>& image_only_probabilities,
                                   bool use_distance_term, const ViewCrfOptions& options);

// Per-pixel class probabilities: every pixel takes its superpixel's row of `marginals` (num_labels
// channels).
ImageF32 PixelProbabilities(const Superpixels& superpixels, const Marginals& marginals);
// Per-pixel labels from per-superpixel labels.
Image<int32_t> PixelLabels(const Superpixels& superpixels, const std::vector<int>& superpixel_labels);

inline double SameLabelFeature(double scaled_distance) { return 1.0 - std::exp(-scaled_distance); }
inline double DifferentLabelFeature(double scaled_distance) { return std::exp(-scaled_distance); }

}  // namespace semvox
