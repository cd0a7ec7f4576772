// k-nearest-neighbour unary of the MST-CRF paper (Sec. 3.3, Eq. 3 and 4): the class probabilities of a
// superpixel from the labels of its k = 10 nearest training observations, normalised by class frequency so
// that frequent classes (walls, floor) do not win every vote.
//
//   Result<KnnClassifier> knn = KnnClassifier::Train(features, dims, labels, num_classes, KnnOptions{});
//   std::vector<double> p = knn->Probabilities(z);   // P_s(x_s = l | z), sums to one
//   unary energy f(x_s = l) = -log p[l]               (Eq. 3)
//
// The kd-tree (nanoflann) stays inside knn_unary.cc.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"

namespace semvox {

// Eq. 4: P(l_j) = r_j / sum_i r_i with r_j = (f_j / fbar_j) (Fbar_j / F_j), where f_j are the neighbours
// with label j (fbar_j = k - f_j those without) and F_j the training observations with label j (Fbar_j =
// N - F_j). Limits the equation leaves open: a class with no training observation gets 0; when every
// neighbour has one label (fbar_j = 0, r_j infinite) that label gets 1; with no neighbour at all the
// distribution is uniform over the classes seen in training.
std::vector<double> ClassFrequencyNormalisedProbability(std::span<const int> neighbour_counts,
                                                        std::span<const int64_t> training_counts);

struct KnnOptions {
  // Neighbours per query (the paper's k). >= 1.
  int k = 10;
  // Probabilities below this are raised to it and the distribution renormalised, so that the unary
  // -log p stays finite when a class got no vote. [0, 1 / num_classes).
  double probability_floor = 1e-3;
  // Scale every feature dimension to zero mean and unit variance over the training set before the
  // kd-tree (the 15 dimensions mix LAB units, metres and ratios).
  bool standardise = true;
  // kd-tree leaf size (nanoflann). >= 1.
  int leaf_max_size = 10;

  bool Check(std::string* error) const;
};

class KnnClassifier {
 public:
  // `features` holds one row of `dims` values per training observation (row-major); `labels` one class
  // in [0, num_classes) per row. Fails on empty or inconsistent input.
  static Result<KnnClassifier> Train(std::vector<float> features, int dims, std::vector<int> labels,
                                     int num_classes, const KnnOptions& options);

  KnnClassifier(KnnClassifier&&) noexcept;
  KnnClassifier& operator=(KnnClassifier&&) noexcept;
  ~KnnClassifier();

  int dims() const;
  int num_classes() const;
  size_t size() const;  // Training observations.
  const std::vector<int64_t>& class_counts() const;  // F_j.
  const KnnOptions& options() const;

  // f_j: labels of the k nearest training observations of `z` (dims() values), counted per class.
  std::vector<int> NeighbourCounts(std::span<const float> z) const;
  // Eq. 4 on NeighbourCounts, then the probability floor.
  std::vector<double> Probabilities(std::span<const float> z) const;
  // The same, and NeighbourDistance (below) from the same search.
  std::vector<double> Probabilities(std::span<const float> z, double* neighbour_distance) const;
  // Mean Euclidean distance from `z` to its k nearest training observations, in the space they are found in
  // (standardised when options().standardise): how far the query lies from everything the model saw.
  double NeighbourDistance(std::span<const float> z) const;
  // NeighbourCounts and NeighbourDistance from one search (NaN distance for a query of the wrong size).
  std::vector<int> NeighbourCountsAndDistance(std::span<const float> z, double* distance) const;
  // The q-quantile (q in [0, 1]) of the training observations' own neighbour distances, each to its k nearest
  // other observations (leave one out). A query farther than the 0.99-quantile is farther from the training set
  // than 99 % of the training observations are from the rest. 0 with fewer than two observations. Costs one
  // search per observation; `max_rows` > 0 takes the quantile over that many observations at an even stride
  // (each still measured against all the others), for large models (the per-view ones' 20,000 rows).
  double TrainingNeighbourDistanceQuantile(double q, size_t max_rows = 0) const;
  // The quantile beyond which the segment and per-view classifiers call a query unfamiliar.
  static constexpr double kFamiliarQuantile = 0.99;

  // Binary model file (features, labels, options); the kd-tree is rebuilt on load.
  Status Save(const std::string& path) const;
  static Result<KnnClassifier> Load(const std::string& path);

 private:
  struct Impl;
  explicit KnnClassifier(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace semvox
